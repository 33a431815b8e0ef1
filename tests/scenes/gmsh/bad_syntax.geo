// Test input for tests/test_gmsh.cpp (GmshErrors): a syntax error on line 3.
Point(1) = {0, 0, 0};
Line(1) = {1, 2;
