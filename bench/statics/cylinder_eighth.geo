// An eighth of the pinched cylinder (bench/statics/gmsh_shells.sh): R 300, x in [0, L/2] with
// L = 600, the quarter circle from the crown (z = R) to the side (y = R); unstructured
// triangles. Physical Surface "shell"; Curves "ends" (diaphragm, x = 0), "mid" (x = L/2),
// "crown" (plane y = 0), "side" (plane z = 0); Point "top" (the load, x = L/2 on the crown).
R = 300; L = 600;
Point(1) = {0, 0, 0};
Point(2) = {0, 0, R};
Point(3) = {0, R, 0};
Circle(1) = {2, 1, 3};
out[] = Extrude {L / 2, 0, 0} { Curve{1}; };
Physical Surface("shell") = {out[1]};
Physical Curve("ends") = {1};
Physical Curve("mid") = {out[0]};
Physical Curve("crown") = {out[3]};
Physical Curve("side") = {out[2]};
pts[] = Boundary{ Curve{out[0]}; };
Physical Point("top") = {Abs(pts[0])};
