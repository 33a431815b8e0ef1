// Pinched hemisphere with an 18 degree hole (MacNeal & Harder 1985), a quarter
// (bench/statics/gmsh_shells.sh): R 10, the shell from the equator (z = 0) up to 18 degrees from
// the pole, x >= 0, y >= 0; unstructured triangles. Physical Surface "shell"; Curves "px" (on
// the plane x = 0) and "py" (on y = 0); Points "A" (R, 0, 0) and "B" (0, R, 0), the loads, and
// "C" (on the hole, in y = 0), where z is held.
R = 10; a = 18 * Pi / 180;
Point(1) = {0, 0, 0};
Point(2) = {R, 0, 0};
Point(3) = {0, R, 0};
Point(4) = {R * Sin(a), 0, R * Cos(a)};
Point(5) = {0, R * Sin(a), R * Cos(a)};
Point(6) = {0, 0, R * Cos(a)};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 5};
Circle(3) = {5, 6, 4};
Circle(4) = {4, 1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Surface(1) = {1} In Sphere {1};
Physical Surface("shell") = {1};
Physical Curve("px") = {2};
Physical Curve("py") = {4};
Physical Point("A") = {2};
Physical Point("B") = {3};
Physical Point("C") = {4};
