// Cantilever plate L = 1 m, H = 0.2 m in the plane z = 0: Physical Surface "plate", the
// clamped root edge x = 0 "root", the loaded tip edge x = L "tip" (split at its midpoint,
// Physical Point "tipmid").
L = 1.0; H = 0.2;
Point(1) = {0, 0, 0};
Point(2) = {L, 0, 0};
Point(3) = {L, H / 2, 0};
Point(4) = {L, H, 0};
Point(5) = {0, H, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 1};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Physical Surface("plate") = {1};
Physical Curve("root") = {5};
Physical Curve("tip") = {2, 3};
Physical Point("tipmid") = {3};
