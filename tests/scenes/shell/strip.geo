// Cantilever strip L = 1 m (along x) by b = 0.5 m in the plane z = 0 (flexsens shell clamp
// tests): Physical Surface "strip", its clamped root x = 0 "root", the middle of its tip
// "tip" (a mesh node).
L = 1.0;
b = 0.5;
Point(1) = {0, 0, 0};
Point(2) = {L, 0, 0};
Point(3) = {L, b / 2, 0};
Point(4) = {L, b, 0};
Point(5) = {0, b, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 1};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Physical Surface("strip") = {1};
Physical Curve("root") = {5};
Physical Point("tip") = {3};
