#!/usr/bin/env python3
"""Cantilever convergence of the meshed bodies (type: solid) with `flexsens static` (not a test).

Plate (plane stress): L = 1 m, H = 0.05 m, thickness 0.01 m; bar (tetrahedra): L = 1 m, square
section 0.1 m. Steel E = 2.1e11 Pa, nu = 0, root face fixed (ground), a small dead load spread
uniformly over the tip face (plate 10 N, bar 100 N, deflection ~1e-4 L: linear range).
Reference (independent): Timoshenko beam P L^3 / (3 E I) + P L / (kappa G A), kappa = 5/6.
Measured: the deflection of the tip's centre node (Physical Point 'tipmid') per element size
h and order; the relative difference to the reference, and the observed rate between sizes.
Writes bench/solid_cantilever/bench.md.

    python3 bench/solid_cantilever_bench.py [--flexsens build/flexsens]
"""
import argparse, csv, math, os, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "bench", "solid_cantilever")
GEO = os.path.join(ROOT, "tests", "scenes", "solid")
E, T = 2.1e11, 0.01


def scene(dim, size, order, P):
    if dim == 2:
        body = ("mesh: %s/plate.geo, group: plate, thickness: %g" % (GEO, T), "[0, %g]" % -P)
    else:
        body = ("mesh: %s/bar3d.geo, group: bar" % GEO, "[0, %g, 0]" % -P)
    return ("dimension: %d\nelements:\n  - {name: body, type: solid, %s, size: %.17g, order: %d, E: %g, nu: 0,"
            " density: 7800, ground: [root], traction: [{group: tip, force: %s}]}\n" % (dim, body[0], size, order, E, body[1]) +
            "static: {load_steps: 1}\noutputs:\n  - {name: tip_y, node: tipmid, component: y}\noutput: {vtk: false}\n")


def timoshenko(P, b, h):
    I, A, G = b * h ** 3 / 12, b * h, E / 2
    return P / (3 * E * I) + P / (5 / 6 * G * A)


def run(exe, dim, size, order, P, wd):
    tag = "d%d_o%d_%g" % (dim, order, size)
    path = os.path.join(wd, tag + ".yaml")
    open(path, "w").write(scene(dim, size, order, P))
    out = os.path.join(wd, tag)
    # the meshes stay in tests/scenes/solid: a scene reads outside its folder only where allowed
    r = subprocess.run([exe, "static", path, "--out", out, "--allow-path", GEO], capture_output=True, text=True)
    if r.returncode != 0:
        print(r.stderr, file=sys.stderr)
        return None, None
    rows = list(csv.DictReader(open(os.path.join(out, "series.csv"))))
    import json
    s = json.load(open(os.path.join(out, "summary.json")))
    y0 = 0.025 if dim == 2 else 0.0  # tipmid's rest y: the plate's mid-height, the bar's axis
    return y0 - float(rows[-1]["tip_y"]), s.get("n", s.get("model", {}).get("n"))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexsens", default=os.path.join(ROOT, "build", "flexsens"))
    a = ap.parse_args()
    os.makedirs(OUT, exist_ok=True)
    lines = ["# Cantilever convergence of meshed bodies (bench/solid_cantilever_bench.py)", "",
             "Reference: Timoshenko beam tip deflection (kappa = 5/6, nu = 0). Tip centre node 'tipmid'.", "",
             "| body | order | h [m] | coordinates n | tip deflection [m] | rel. difference | rate |",
             "|---|---|---|---|---|---|---|"]
    conv = []
    with tempfile.TemporaryDirectory() as wd:
        for dim, H, P, b, sizes in [(2, 0.05, 10.0, T, [0.05, 0.025, 0.0125, 0.00625]),
                                     (3, 0.1, 100.0, 0.1, [0.2, 0.1, 0.05, 0.025])]:
            ref = timoshenko(P, b, H)
            for order in (1, 2):
                prev = None
                for h in sizes:
                    w, n = run(a.flexsens, dim, h, order, P, wd)
                    if w is None:
                        continue
                    err = abs(w / ref - 1)
                    rate = "" if prev is None else "%.2f" % (math.log(prev[1] / err) / math.log(prev[0] / h))
                    prev = (h, err)
                    if order == 2:
                        conv.append((dim, h, w))
                    lines.append("| %s | %d | %g | %s | %.6e | %.2e | %s |" % ("plate" if dim == 2 else "bar", order, h, n,
                                                                              w, err, rate))
                    print(lines[-1], flush=True)
            lines.append("| Timoshenko | | | | %.6e | | |" % ref)
            # Converged reference: the finest quadratic mesh; differences of the coarser ones.
            mine = [c for c in conv if c[0] == dim]
            if len(mine) > 2:
                wf = mine[-1][2]
                lines.append("")
                lines.append("%s, quadratic elements against the finest (h = %g): " % ("plate" if dim == 2 else "bar", mine[-1][1]) +
                             ", ".join("h = %g: %.2e" % (h, abs(w / wf - 1)) for _, h, w in mine[:-1]))
                if dim == 2:
                    lines += ["", "| body | order | h [m] | coordinates n | tip deflection [m] | rel. difference | rate |",
                              "|---|---|---|---|---|---|---|"]
    open(os.path.join(OUT, "bench.md"), "w").write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
