// A quarter of the ellipse x = 2 cos(t), y = sin(t) from (2, 0) to (0, 1) (centre at the origin,
// major axis point (2, 0)): a curve whose tangents the chain's chords do not fit exactly.
Point(1) = {2, 0, 0};
Point(2) = {0, 0, 0};
Point(3) = {0, 1, 0};
Ellipse(1) = {1, 2, 1, 3};
Physical Point("start") = {1};
Physical Curve("quarter") = {1};
