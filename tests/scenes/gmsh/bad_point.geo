// Test input for tests/test_gmsh.cpp (GmshErrors): a Physical Point holding two points.
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Line(1) = {1, 2};
Physical Curve("rod") = {1};
Physical Point("ends") = {1, 2};
