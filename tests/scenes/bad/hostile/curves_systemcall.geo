// geometry: {gmsh: ...} (beam curves): a shell command through the other Gmsh entry point.
SystemCall "echo GEOMETRY-SYSTEMCALL-RAN > geometry_marker.txt";
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Line(1) = {1, 2};
Physical Curve("rod") = {1};
Physical Point("A") = {1};
Physical Point("B") = {2};
