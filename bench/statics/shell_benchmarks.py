#!/usr/bin/env python3
"""Scenes of the two classic shell benchmarks for `flexsens static`, written as a user would
from docs/scene-reference.md: a Gmsh .msh (ASCII 2.2) of near-equilateral triangles (the
discrete shell's hinge energy is isotropic only on such meshes, docs/theory.md) and a scene
whose diaphragm ends hold the two in-plane displacement components of each end node with a
`support: [{group: ends, fix: [y, z]}]` on the shell (the axial one stays free).

  roof N      Scordelis-Lo roof: R 25, L 50, t 0.25, E 4.32e8, nu 0, 90 per unit area
              (gravity 10 x density 36 x t), 80 deg span, diaphragm ends; N elements along L.
              Reference vertical midside displacement of the free edge 0.3024 (MacNeal-Harder).
  cylinder N  Pinched cylinder with diaphragms: R 300, L 600, t 3, E 3e6, nu 0.3, P = 1
              at top and bottom of the middle section; full cylinder; N elements along L.
              Reference radial displacement under the load 1.8248e-5.

  eighth N    The pinched cylinder's eighth (symmetry planes x = L/2, y = 0, z = 0, load P/4).

usage: shell_benchmarks.py roof|cylinder|eighth N OUTDIR
The environment variables BENDING (hinges or kirchhoff, default hinges) and MEMBRANE (cst or
patch, default patch with kirchhoff, cst with hinges) pick the shell's `bending:` and
`membrane:`.
"""
import math
import os
import sys

BENDING = os.environ.get("BENDING", "hinges")
MEMBRANE = os.environ.get("MEMBRANE", "patch" if BENDING == "kirchhoff" else "cst")


def lattice(nx, ns, lx, ls, periodic):
    """Triangular lattice on [0, lx] x [0, ls] (param space x, s): even rows at x = i hx,
    odd rows at (i + 1/2) hx plus both ends, so the ends x = 0, lx are straight. Returns
    nodes [(x, s)], rows (lists of node indices) and triangles (counter-clockwise in x, s)."""
    hx = lx / nx
    nrows = ns if periodic else ns + 1
    nodes, rows = [], []
    for j in range(nrows):
        xs = [i * hx for i in range(nx + 1)] if j % 2 == 0 else \
            [0.0] + [(i + 0.5) * hx for i in range(nx)] + [lx]
        rows.append([len(nodes) + k for k in range(len(xs))])
        nodes += [(x, j * ls / ns) for x in xs]
    tris = []
    for j in range(ns):
        bot, top = rows[j], rows[(j + 1) % nrows]
        a = b = 0
        while a < len(bot) - 1 or b < len(top) - 1:
            adv_bot = b == len(top) - 1 or (a < len(bot) - 1 and nodes[bot[a + 1]][0] <= nodes[top[b + 1]][0])
            if adv_bot:
                tris.append((bot[a], bot[a + 1], top[b]))
                a += 1
            else:
                tris.append((bot[a], top[b + 1], top[b]))
                b += 1
    return nodes, rows, tris


def write_msh(path, xyz, tris, points, ends):
    """Gmsh ASCII 2.2: Physical Surface 1 "shell", one Physical Point per (name, node), and
    Physical Curves: "ends" (the diaphragm edges) as the segments (a, b) of `ends`, or one per
    (name, segments) when `ends` is a dict."""
    curves = ends if isinstance(ends, dict) else {"ends": ends}
    with open(path, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n%d\n" % (1 + len(points) + len(curves)))
        f.write('2 1 "shell"\n')
        for k, (name, _) in enumerate(points):
            f.write('0 %d "%s"\n' % (k + 2, name))
        tags = {}
        for k, name in enumerate(curves):
            tags[name] = len(points) + 2 + k
            f.write('1 %d "%s"\n' % (tags[name], name))
        f.write("$EndPhysicalNames\n$Nodes\n%d\n" % len(xyz))
        for i, p in enumerate(xyz):
            f.write("%d %.17g %.17g %.17g\n" % (i + 1, p[0], p[1], p[2]))
        nseg = sum(len(v) for v in curves.values())
        f.write("$EndNodes\n$Elements\n%d\n" % (len(tris) + len(points) + nseg))
        eid = 1
        for k, (_, node) in enumerate(points):
            f.write("%d 15 2 %d %d %d\n" % (eid, k + 2, k + 1, node + 1))
            eid += 1
        for name, segs in curves.items():
            for a, b in segs:
                f.write("%d 1 2 %d %d %d %d\n" % (eid, tags[name], tags[name], a + 1, b + 1))
                eid += 1
        for t in tris:
            f.write("%d 2 2 1 1 %d %d %d\n" % (eid, t[0] + 1, t[1] + 1, t[2] + 1))
            eid += 1
        f.write("$EndElements\n")


def end_segments(rows, periodic):
    """The segments along both ends x = 0 and x = L: consecutive rows' first (last) nodes."""
    count = len(rows) if periodic else len(rows) - 1
    return [(rows[j][k], rows[(j + 1) % len(rows)][k]) for k in (0, -1) for j in range(count)]


def node_name(i, named):
    return named.get(i, "shell.%d" % (i + 1))


def roof(n, outdir):
    R, L, span = 25.0, 50.0, math.radians(80.0)
    ls = R * span
    ns = max(2, 2 * round(ls / (L / n * math.sqrt(3) / 2) / 2))  # even: the free edges are even rows
    nodes, rows, tris = lattice(n, ns, L, ls, False)
    xyz = [(x, R * math.sin(s / R - span / 2), R * math.cos(s / R - span / 2)) for x, s in nodes]
    mid = rows[0][n // 2]  # free edge (theta = -40 deg), x = L/2
    named = {mid: "midside"}
    write_msh(os.path.join(outdir, "roof_%d.msh" % n), xyz, tris, [("midside", mid)], end_segments(rows, False))
    lines = ["# Scordelis-Lo roof, %d x %d lattice, %d nodes (bench/statics/shell_benchmarks.py)" % (n, ns, len(xyz)),
             "dimension: 3", "gravity: [0, 0, -10]", "elements:",
             "  - {name: shell, type: shell, mesh: roof_%d.msh, group: shell, E: 4.32e8, nu: 0.0," % n,
             "     density: 36, thickness: 0.25, bending: %s, membrane: %s, support: [{group: ends, fix: [y, z]}]}" % (BENDING, MEMBRANE), "constraints:"]
    # the axial rigid motion: the free edges' middle nodes hold x (zero by symmetry)
    for k, node in enumerate((mid, rows[ns][n // 2])):
        lines.append("  - {name: axial%d, type: prescribed_coordinate, node: %s, axis: x, "
                     "function: {type: constant, value: 0}}" % (k, node_name(node, named)))
    lines += ["static: {load_steps: 1}", "outputs:", "  - {name: midside_z, node: midside, component: z}"]
    path = os.path.join(outdir, "roof_%d.yaml" % n)
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path, len(xyz)


def cylinder(n, outdir):
    R, L = 300.0, 600.0
    ls = 2 * math.pi * R
    ns = max(4, 4 * round(ls / (L / n * math.sqrt(3) / 2) / 4))  # the bottom row is even too
    nodes, rows, tris = lattice(n, ns, L, ls, True)
    xyz = [(x, R * math.sin(s / R), R * math.cos(s / R)) for x, s in nodes]
    top, bottom = rows[0][n // 2], rows[ns // 2][n // 2]
    named = {top: "top", bottom: "bottom"}
    write_msh(os.path.join(outdir, "cylinder_%d.msh" % n), xyz, tris, [("top", top), ("bottom", bottom)],
              end_segments(rows, True))
    lines = ["# Pinched cylinder with diaphragms, %d x %d lattice, %d nodes (bench/statics/shell_benchmarks.py)"
             % (n, ns, len(xyz)), "dimension: 3", "gravity: [0, 0, 0]", "elements:",
             "  - {name: shell, type: shell, mesh: cylinder_%d.msh, group: shell, E: 3.0e6, nu: 0.3," % n,
             "     density: 1, thickness: 3.0, bending: %s, membrane: %s, support: [{group: ends, fix: [y, z]}]}" % (BENDING, MEMBRANE),
             "  - {name: P_top, type: point_force, node: top, force: [0, 0, -1]}",
             "  - {name: P_bottom, type: point_force, node: bottom, force: [0, 0, 1]}", "constraints:"]
    # the axial rigid motion: the loaded points hold x (zero by symmetry)
    for name in ("top", "bottom"):
        lines.append("  - {name: axial_%s, type: prescribed_coordinate, node: %s, axis: x, "
                     "function: {type: constant, value: 0}}" % (name, name))
    lines += ["static: {load_steps: 1}", "outputs:", "  - {name: top_z, node: top, component: z}",
              "  - {name: bottom_z, node: bottom, component: z}"]
    path = os.path.join(outdir, "cylinder_%d.yaml" % n)
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path, len(xyz)


def eighth(n, outdir):
    """An eighth of the pinched cylinder: x in [0, L/2] (diaphragm at x = 0, symmetry plane x =
    L/2), the quarter circle from the top (theta = 0, plane y = 0) to the side (theta = 90 deg,
    plane z = 0), P/4 at the top of the middle section; N elements along the full length L."""
    R, L = 300.0, 600.0
    ls = math.pi / 2 * R
    nx = n // 2
    ns = max(2, 2 * round(ls / (L / n * math.sqrt(3) / 2) / 2))
    nodes, rows, tris = lattice(nx, ns, L / 2, ls, False)
    xyz = [(x, R * math.sin(s / R), R * math.cos(s / R)) for x, s in nodes]
    top = rows[0][-1]
    first = [r[0] for r in rows]
    last = [r[-1] for r in rows]
    curves = {"ends": list(zip(first[:-1], first[1:])), "mid": list(zip(last[:-1], last[1:])),
              "crown": list(zip(rows[0][:-1], rows[0][1:])), "side": list(zip(rows[ns][:-1], rows[ns][1:]))}
    write_msh(os.path.join(outdir, "eighth_%d.msh" % n), xyz, tris, [("top", top)], curves)
    lines = ["# Pinched cylinder, an eighth: %d x %d lattice, %d nodes (bench/statics/shell_benchmarks.py)"
             % (nx, ns, len(xyz)), "dimension: 3", "gravity: [0, 0, 0]", "elements:",
             "  - {name: shell, type: shell, mesh: eighth_%d.msh, group: shell, E: 3.0e6, nu: 0.3," % n,
             "     density: 1, thickness: 3.0, bending: %s, membrane: %s, support: [{group: ends, fix: [y, z]}]," % (BENDING, MEMBRANE),
             "     symmetry: [{group: mid, normal: x}, {group: crown, normal: y}, {group: side, normal: z}]}",
             "  - {name: P_top, type: point_force, node: top, force: [0, 0, -0.25]}",
             "static: {load_steps: 1}", "outputs:", "  - {name: top_z, node: top, component: z}"]
    path = os.path.join(outdir, "eighth_%d.yaml" % n)
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path, len(xyz)


if __name__ == "__main__":
    kind, n, outdir = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    os.makedirs(outdir, exist_ok=True)
    path, nn = {"roof": roof, "cylinder": cylinder, "eighth": eighth}[kind](n, outdir)
    print(path, nn)
