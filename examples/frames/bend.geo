// Bathe-Bolourchi bend: a 45-degree arc of radius 100 in the x-y plane from the origin
// (tangent +x) about the centre (0, 100, 0).
Point(1) = {0, 0, 0};
Point(2) = {0, 100, 0};
Point(3) = {100 * Sin(Pi / 4), 100 * (1 - Cos(Pi / 4)), 0};
Circle(1) = {1, 2, 3};
Physical Point("root") = {1};
Physical Point("tip") = {3};
Physical Curve("arc") = {1};
