// Slender cantilever strip L = 1 m, H = L/50 in the plane z = 0 (flexsens solid elastica test,
// tests/test_solid_elastica.cpp). Physical Surface "strip"; root edge x = 0 ("root"), tip
// edge x = L ("tip").
L = 1.0; H = 0.02;
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
Physical Surface("strip") = {1};
Physical Curve("root") = {4};
Physical Curve("tip") = {2};
