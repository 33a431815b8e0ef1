// An 80 GB list built by the .geo parser: only the memory limit of the Gmsh child ends it.
Include "panel.geo";
x[] = {1:1e10};
