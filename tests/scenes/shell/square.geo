// Square plate a = 1 m in the plane z = 0 (flexsens shell tests): Physical Surface "plate",
// its four edges "edges" (simply supported when grounded: no hinge on a boundary edge; clamped
// with `clamp: [edges]`), the
// corner "corner" and the centre "centre" (a mesh node).
a = 1.0;
Point(1) = {0, 0, 0};
Point(2) = {a, 0, 0};
Point(3) = {a, a, 0};
Point(4) = {0, a, 0};
Point(5) = {a / 2, a / 2, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Point{5} In Surface{1};
Physical Surface("plate") = {1};
Physical Curve("edges") = {1, 2, 3, 4};
Physical Point("corner") = {1};
Physical Point("centre") = {5};
