// A quarter of the ellipse x = 20 cos(t), y = 10 sin(t) from (20, 0) to (0, 10) (centre at the
// origin, major axis point (20, 0)): a curve whose tangents the chain's chords do not fit exactly.
Point(1) = {20, 0, 0};
Point(2) = {0, 0, 0};
Point(3) = {0, 10, 0};
Ellipse(1) = {1, 2, 1, 3};
Physical Point("start") = {1};
Physical Curve("quarter") = {1};
