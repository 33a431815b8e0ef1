// Plane-stress patch 2 x 1 m in the plane z = 0 for the linear statics test
// (tests/test_static_linear.cpp): a structured mesh whose left edge has only its two corners
// ("A" at the origin, "B" at (0, 1)), so that the supports are two prescribed coordinates per
// corner; right edge "right" carries the traction.
L = 2.0; H = 1.0;
Point(1) = {0, 0, 0};
Point(2) = {L, 0, 0};
Point(3) = {L, H, 0};
Point(4) = {0, H, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve {1, 3} = 5;
Transfinite Curve {2} = 3;
Transfinite Curve {4} = 2;
Physical Surface("patch") = {1};
Physical Curve("right") = {2};
Physical Point("A") = {1};
Physical Point("B") = {4};
Physical Point("C") = {3};
