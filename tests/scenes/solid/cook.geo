// Cook's membrane (tapered panel, 48 x 44/16, the classic units): Physical Surface "cook",
// clamped edge x = 0 "clamp", loaded edge x = 48 "load", its top corner "C".
Point(1) = {0, 0, 0};
Point(2) = {48, 44, 0};
Point(3) = {48, 60, 0};
Point(4) = {0, 44, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Surface("cook") = {1};
Physical Curve("clamp") = {4};
Physical Curve("load") = {2};
Physical Point("C") = {3};
