// Cook's membrane (Cook 1974): the tapered panel with corners (0, 0), (48, 0 + 44), (48, 60),
// (0, 44), i.e. left edge 44 high, right edge 16 high. Left edge "left" clamped, right edge
// "right" carries the shear load; "C" the right edge's midpoint (48, 52), the reference point
// of the published 23.96; "corner" the top right corner (48, 60).
Point(1) = {0, 0, 0};
Point(2) = {48, 44, 0};
Point(3) = {48, 60, 0};
Point(4) = {0, 44, 0};
Point(5) = {48, 52, 0};
Line(1) = {1, 2};
Line(2) = {2, 5};
Line(5) = {5, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 5, 3, 4};
Plane Surface(1) = {1};
Physical Surface("panel") = {1};
Physical Curve("left") = {4};
Physical Curve("right") = {2, 5};
Physical Point("C") = {5};
Physical Point("corner") = {3};
