// An endless loop: only the CPU-time limit of the Gmsh child ends it.
Include "panel.geo";
x = 0;
For i In {1:1e15}
  x = x + 1;
EndFor
