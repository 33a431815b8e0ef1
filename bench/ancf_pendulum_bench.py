#!/usr/bin/env python3
"""Flexible-pendulum work-precision (not a test): positions-only beam vs ANCF cable.

L = 1 m, square side 0.02 m, density 7850 kg/m^3, E = 2e8 Pa, pinned at the origin, released
horizontal under gravity, 1 s, trapezoidal rule. Tip position error at t = 1 s against a
reference versus the CPU time of each run (summary.json's wall_time_s on this machine).
Default: the full work-precision sweep over N and dt, reference ANCF N = 32, dt = 1.25e-4 s.
--spatial: the discretization in space only: every run and the reference (ANCF, N = 32) at
the same dt = 5e-4 s, so the time-stepping error largely cancels.
Writes bench/ancf_pendulum/bench.md and bench.csv.

    python3 bench/ancf_pendulum_bench.py [--flexsens build/flexsens] [--spatial]
"""
import argparse, csv, json, math, os, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "bench", "ancf_pendulum")


def scene(kind, n, dt):
    nodes = "".join("  - {name: n%d, position: [%.17g, 0]%s}\n" % (i, i / n, ", ground: true" if i == 0 else "")
                    for i in range(n + 1))
    chain = ", ".join("n%d" % i for i in range(n + 1))
    return ("dimension: 2\ngravity: [0, -9.81]\nnodes:\n" + nodes +
            "elements:\n  - {name: rod, type: %s, nodes: [%s], E: 2.0e8, density: 7850, section: {side: 0.02}}\n" % (kind, chain) +
            "integrator: {type: trapezoidal, t_end: 1.0, dt: %g, frame_interval: 1.0}\n" % dt +
            "outputs:\n  - {name: x_tip, node: n%d, component: x}\n  - {name: y_tip, node: n%d, component: y}\n" % (n, n) +
            "output: {vtk: false}\n")


def run(exe, kind, n, dt, wd):
    tag = "%s_%d_%g" % (kind, n, dt)
    path = os.path.join(wd, tag + ".yaml")
    open(path, "w").write(scene(kind, n, dt))
    out = os.path.join(wd, tag)
    r = subprocess.run([exe, "run", path, "--out", out], capture_output=True, text=True)
    if r.returncode != 0:
        return None
    rows = list(csv.DictReader(open(os.path.join(out, "series.csv"))))
    s = json.load(open(os.path.join(out, "summary.json")))
    return float(rows[-1]["x_tip"]), float(rows[-1]["y_tip"]), s["wall_time_s"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexsens", default=os.path.join(ROOT, "build", "flexsens"))
    ap.add_argument("--spatial", action="store_true")
    a = ap.parse_args()
    Ns = {"beam": [4, 8, 16, 32], "ancf_cable": [2, 4, 8, 16]}
    dts = [5e-4] if a.spatial else [4e-3, 2e-3, 1e-3, 5e-4]
    refdt = 5e-4 if a.spatial else 1.25e-4
    with tempfile.TemporaryDirectory() as wd:
        ref = run(a.flexsens, "ancf_cable", 32, refdt, wd)
        if ref is None:
            sys.exit("reference run failed")
        res = []
        for kind, ns in Ns.items():
            for n in ns:
                for dt in dts:
                    r = run(a.flexsens, kind, n, dt, wd)
                    err = math.hypot(r[0] - ref[0], r[1] - ref[1]) if r else float("nan")
                    res.append((kind, n, dt, err, r[2] if r else float("nan")))
                    print(kind, n, dt, "%.3e" % err, r[2] if r else "failed", flush=True)
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "bench.csv"), "w") as f:
        f.write("element,N,dt,tip_error_m,cpu_s\n")
        for row in res:
            f.write("%s,%d,%g,%.6e,%.4f\n" % row)
    with open(os.path.join(OUT, "bench.md"), "w") as f:
        f.write("# Flexible pendulum: positions-only beam vs ANCF cable (trapezoidal, 1 s)\n\n")
        f.write("Reference: ANCF N = 32, dt = %g s, tip (%.9f, %.9f) m. Error = |tip - reference| at t = 1 s.\n"
                "CPU = wall time of the run on a shared, busy 2-core machine (indicative only).\n\n" % (refdt, ref[0], ref[1]))
        f.write("| element | N | dt [s] | tip error [m] | CPU [s] |\n|---|---|---|---|---|\n")
        for row in res:
            f.write("| %s | %d | %g | %.3e | %.3f |\n" % row)


if __name__ == "__main__":
    main()
