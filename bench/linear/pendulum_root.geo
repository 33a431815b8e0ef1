// The 3D solid pendulum's bar (examples/solid/pendulum3d.geo) with its end face x = 0 as the
// Physical Surface "root" as well as the hinge edge: bench/linear/constrained.sh welds either
// to a hinged rigid body or holds it by support rows.
SetFactory("OpenCASCADE");
L = 0.5; H = 0.04; e = 1e-6;
Box(1) = {0, -H / 2, -H / 2, L, H, H};
Point(100) = {L, 0, 0};
Point{100} In Surface{2};  // the tip centre, a mesh node
Physical Volume("bar") = {1};
Physical Curve("hinge") = Curve In BoundingBox{-e, H / 2 - e, -H, e, H / 2 + e, H};
Physical Surface("root") = Surface In BoundingBox{-e, -H, -H, e, H, H};
Physical Surface("tip") = Surface In BoundingBox{L - e, -H, -H, L + e, H, H};
Physical Point("tip") = {100};
