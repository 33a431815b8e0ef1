// Link 1-2 of the five-bar as a plate (examples/fivebar/meshed_link.yaml): a rectangle of
// width w = 0.05 m from joint n1 (-1, -1) to joint n2 (0.5, -2) in the scene's x-z plane
// (Gmsh x, y = scene x, z); the joints are the midpoints of its short edges.
L = Sqrt(3.25); w = 0.05;
nx = 1 / L; ny = 1.5 / L;   // unit normal to the link's axis (1.5, -1) / L
Point(1) = {-1, -1, 0};
Point(2) = {0.5, -2, 0};
Point(3) = {-1 + nx * w / 2, -1 + ny * w / 2, 0};
Point(4) = {0.5 + nx * w / 2, -2 + ny * w / 2, 0};
Point(5) = {0.5 - nx * w / 2, -2 - ny * w / 2, 0};
Point(6) = {-1 - nx * w / 2, -1 - ny * w / 2, 0};
Line(1) = {6, 5};
Line(2) = {5, 2};
Line(3) = {2, 4};
Line(4) = {4, 3};
Line(5) = {3, 1};
Line(6) = {1, 6};
Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};
Physical Surface("link") = {1};
Physical Point("n1") = {1};
Physical Point("n2") = {2};
