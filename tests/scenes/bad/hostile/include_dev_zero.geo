// Include of a device outside the scene's folder (Gmsh would read zeros for ever).
Include "panel.geo";
Include "/dev/zero";
