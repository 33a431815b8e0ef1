#!/usr/bin/env python3
"""Writes plate_half.msh and plate_full.msh (MSH 2.2, linear triangles) for the shell symmetry
test (tests/test_supports.cpp): a plate 1 x 1 m in z = 0, x in [0, 1], clamped at x = 0
("root"), point "tipmid" at (1, 0, 0). The full plate (y in [-0.5, 0.5]) is the half plate
(y in [0, 0.5], symmetry edge y = 0 "sym") and its mirror image across y = 0, triangles wound
the same way, so that the half model with a symmetry plane must reproduce the full one."""
import pathlib

NX, NY = 8, 4  # cells along x, across the half width


def plate(full):
    nodes, index = [], {}
    rows = range(-NY, NY + 1) if full else range(0, NY + 1)
    for j in rows:
        for i in range(NX + 1):
            index[(i, j)] = len(nodes) + 1
            nodes.append((i / NX, 0.5 * j / NY))
    tris = []
    for j in (range(-NY, NY) if full else range(0, NY)):
        for i in range(NX):
            a, b, c, d = index[(i, j)], index[(i + 1, j)], index[(i + 1, j + 1)], index[(i, j + 1)]
            # upper half: diagonal a-c; lower half: the mirror image (diagonal d-b), same winding
            tris += [(a, b, c), (a, c, d)] if j >= 0 else [(a, b, d), (b, c, d)]
    root = [(index[(0, j)], index[(0, j + 1)]) for j in (range(-NY, NY) if full else range(0, NY))]
    sym = [] if full else [(index[(i, 0)], index[(i + 1, 0)]) for i in range(NX)]
    return nodes, tris, root, sym, index[(NX, 0)]


def write(path, full):
    nodes, tris, root, sym, tip = plate(full)
    names = [(2, 1, "plate"), (1, 2, "root"), (0, 4, "tipmid")] + ([] if full else [(1, 3, "sym")])
    elems = [(15, 4, (tip,))] + [(1, 2, e) for e in root] + [(1, 3, e) for e in sym] + [(2, 1, t) for t in tris]
    out = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(names))]
    out += [f'{d} {tag} "{n}"' for d, tag, n in names]
    out += ["$EndPhysicalNames", "$Nodes", str(len(nodes))]
    out += [f"{k + 1} {x:.17g} {y:.17g} 0" for k, (x, y) in enumerate(nodes)]
    out += ["$EndNodes", "$Elements", str(len(elems))]
    out += [f"{k + 1} {t} 2 {phys} {phys} " + " ".join(map(str, ns)) for k, (t, phys, ns) in enumerate(elems)]
    out += ["$EndElements", ""]
    pathlib.Path(path).write_text("\n".join(out))


if __name__ == "__main__":
    here = pathlib.Path(__file__).parent
    write(here / "plate_half.msh", False)
    write(here / "plate_full.msh", True)
