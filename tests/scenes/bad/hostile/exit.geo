// Exit ends Gmsh before the geometry is returned.
Include "panel.geo";
Exit;
