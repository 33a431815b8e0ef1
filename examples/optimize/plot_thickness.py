#!/usr/bin/env python3
"""The optimized thickness of each triangle of plate_thickness.yaml, from the optimize folder's
optimum.vtu (Debian's python3-vtk9 and matplotlib):
   python3 examples/optimize/plot_thickness.py <optimize folder> [out.png]
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader  # noqa: E402


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    folder = sys.argv[1]
    out = sys.argv[2] if len(sys.argv) == 3 else os.path.join(folder, "thickness.png")
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(folder, "optimum.vtu"))
    reader.Update()
    grid = reader.GetOutput()
    xy = vtk_to_numpy(grid.GetPoints().GetData())[:, :2]
    cells = [[grid.GetCell(c).GetPointId(k) for k in range(3)] for c in range(grid.GetNumberOfCells())]
    t = vtk_to_numpy(grid.GetCellData().GetArray("t")) * 1000.0  # [mm]
    fig, ax = plt.subplots(figsize=(8, 2.4))
    pc = ax.tripcolor(mtri.Triangulation(xy[:, 0], xy[:, 1], cells), facecolors=t, cmap="viridis", edgecolors="none")
    fig.colorbar(pc, ax=ax, label="thickness [mm]")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m] (clamped at x = 0, 1 kN up at the tip)")
    ax.set_ylabel("y [m]")
    ax.set_title("optimized thickness per triangle (%d), mass held at 15.6 kg" % len(t), fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
