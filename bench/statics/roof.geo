// Scordelis-Lo roof (bench/statics/gmsh_shells.sh): R 25, L 50, 80 deg span about the z axis
// direction, the axis along x; unstructured triangles. Physical Surface "shell", the diaphragm
// ends "ends" (the arcs at x = 0, L), the free edges' midpoints "midside" (y < 0) and "midside2".
R = 25; L = 50; a = 40 * Pi / 180;
Point(1) = {0, 0, 0};
Point(2) = {0, -R * Sin(a), R * Cos(a)};
Point(3) = {0, R * Sin(a), R * Cos(a)};
Circle(1) = {2, 1, 3};
first[] = Extrude {L / 2, 0, 0} { Curve{1}; };
second[] = Extrude {L / 2, 0, 0} { Curve{first[0]}; };
Physical Surface("shell") = {first[1], second[1]};
Physical Curve("ends") = {1, second[0]};
mids[] = Boundary{ Curve{first[0]}; };
Physical Point("midside") = {Abs(mids[0])};
Physical Point("midside2") = {Abs(mids[1])};
