#!/usr/bin/env python3
"""Bathe-Bolourchi 45-degree bend (Bathe & Bolourchi 1979; Simo & Vu-Quoc 1986): a cantilever
on a quarter-octant arc of radius 100 in the x-y plane, unit square section, E = 1e7, nu = 0,
clamped at the origin (tangent +x), tip load 600 along +z in load steps. Published tip
position (47.23, 15.79, 53.37) (Simo & Vu-Quoc 1986, also Bathe & Bolourchi 1979: 47.2, 15.9, 53.4).

Usage: bathe_bolourchi.py FLEXSENS OUTDIR [N ...]   (writes the scenes, runs `flexsens static`,
prints the tip and its error relative to the tip displacement)."""
import csv, math, os, subprocess, sys

REFERENCE = (47.23, 15.79, 53.37)
R, ANGLE, LOAD = 100.0, math.pi / 4, 600.0


def scene(n, steps=20):
    nodes = []
    for j in range(n + 1):
        th = ANGLE * j / n
        extra = ", ground: true, clamped: true" if j == 0 else ""
        nodes.append(f"  - {{name: n{j}, position: [{R * math.sin(th)!r}, {R * (1 - math.cos(th))!r}, 0]{extra}}}")
    names = ", ".join(f"n{j}" for j in range(n + 1))
    return "\n".join([
        "dimension: 3",
        "nodes:", *nodes,
        "elements:",
        f"  - {{name: bend, type: ancf_beam, nodes: [{names}], E: 1.0e7, nu: 0.0, density: 1.0,",
        "     section: {side: 1.0}, y_axis: [0, 0, 1]}",
        f"  - {{name: load, type: point_force, node: n{n}, force: [0, 0, {LOAD}]}}",
        "outputs:",
        *[f"  - {{name: tip_{c}, node: n{n}, component: {c}}}" for c in "xyz"],
        "integrator: {type: trapezoidal, t_end: 1.0, dt: 1.0}",
        f"static: {{load_steps: {steps}}}",
        "output: {vtk: false}",
        ""])


def tip(series):
    with open(series) as f:
        rows = list(csv.DictReader(f))
    last = rows[-1]
    return tuple(float(last[f"tip_{c}"]) for c in "xyz")


def main():
    flexsens, out = sys.argv[1], sys.argv[2]
    counts = [int(a) for a in sys.argv[3:]] or [4, 8, 16, 32]
    os.makedirs(out, exist_ok=True)
    start = (R * math.sin(ANGLE), R * (1 - math.cos(ANGLE)), 0.0)
    u_ref = math.dist(REFERENCE, start)
    print(f"{'N':>4} {'x':>9} {'y':>9} {'z':>9} {'err/|u|':>9} {'cpu s':>7}")
    for n in counts:
        path = os.path.join(out, f"bend_{n}.yaml")
        with open(path, "w") as f:
            f.write(scene(n))
        before = os.times()
        run = subprocess.run([flexsens, "static", path, "--out", os.path.join(out, f"bend_{n}")],
                             capture_output=True, text=True)
        after = os.times()
        cpu = (after.children_user - before.children_user) + (after.children_system - before.children_system)
        if run.returncode != 0:
            print(f"{n:>4} failed: {run.stderr.strip()[-300:]}")
            continue
        x = tip(os.path.join(out, f"bend_{n}", "series.csv"))
        err = math.dist(x, REFERENCE) / u_ref
        print(f"{n:>4} {x[0]:9.3f} {x[1]:9.3f} {x[2]:9.3f} {err:9.2e} {cpu:7.2f}")


if __name__ == "__main__":
    main()
