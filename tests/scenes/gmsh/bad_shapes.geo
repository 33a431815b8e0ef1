// Test input for tests/test_gmsh.cpp (GmshErrors): groups whose curves are not one open chain,
// and two groups sharing a curve. Each group is fine to mesh on its own, except as noted.

// tee: three lines meeting at O (a branch).
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Point(3) = {0, 1, 0};
Point(4) = {-1, 0, 0};
Line(1) = {1, 2};
Line(2) = {1, 3};
Line(3) = {1, 4};
Physical Curve("tee") = {1, 2, 3};
Physical Point("O") = {1};

// ring: a closed triangle.
Point(11) = {0, 0, 1};
Point(12) = {1, 0, 1};
Point(13) = {0, 1, 1};
Line(11) = {11, 12};
Line(12) = {12, 13};
Line(13) = {13, 11};
Physical Curve("ring") = {11, 12, 13};

// pieces: two separate lines.
Point(21) = {0, 0, 2};
Point(22) = {1, 0, 2};
Point(23) = {0, 1, 2};
Point(24) = {1, 1, 2};
Line(21) = {21, 22};
Line(22) = {23, 24};
Physical Curve("pieces") = {21, 22};

// lasso: an open line plus a separate closed triangle.
Point(31) = {0, 0, 3};
Point(32) = {1, 0, 3};
Point(33) = {0, 1, 3};
Point(34) = {5, 5, 3};
Point(35) = {6, 5, 3};
Line(31) = {31, 32};
Line(32) = {32, 33};
Line(33) = {33, 31};
Line(34) = {34, 35};
Physical Curve("lasso") = {34, 31, 32, 33};

// left and right share line 41.
Point(41) = {0, 0, 4};
Point(42) = {1, 0, 4};
Point(43) = {2, 0, 4};
Line(41) = {41, 42};
Line(42) = {42, 43};
Physical Curve("left") = {41};
Physical Curve("right") = {41, 42};
