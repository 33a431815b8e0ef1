// Cantilever bar L = 1 m with a square section H = 0.1 m (flexsens solid tests).
// Physical Volume "bar"; faces x = 0 ("root") and x = L ("tip"); tip centre "tipmid".
SetFactory("OpenCASCADE");
L = 1.0; H = 0.1; e = 1e-6;
Box(1) = {0, -H / 2, -H / 2, L, H, H};
Point(100) = {L, 0, 0};
Point{100} In Surface{2};
Physical Volume("bar") = {1};
Physical Surface("root") = Surface In BoundingBox{-e, -H, -H, e, H, H};
Physical Surface("tip") = Surface In BoundingBox{L - e, -H, -H, L + e, H, H};
Physical Point("tipmid") = {100};
