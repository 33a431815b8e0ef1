#!/usr/bin/env python3
"""Flexible five-bar: beam 1-2 as a positions-only beam (examples/fivebar/flexible.yaml) and as
ANCF cable elements (flexible_ancf.yaml), every case F1-F6 and F1R-F6R, 5 s of the scenes'
trapezoidal rule (dt 1 ms). How far apart are z2 and dz2/dp, and at what CPU cost (not a test).

    python3 bench/fivebar_ancf_bench.py [--flexsens build/flexsens]
Writes bench/fivebar_ancf/bench.md.
"""
import argparse, csv, os, resource, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CASES = ["F%d" % i for i in range(1, 7)] + ["F%dR" % i for i in range(1, 7)]


def run(exe, scene, out):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run([exe, "run", os.path.join(ROOT, "examples", "fivebar", scene), "--out", out],
                       capture_output=True, text=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.exit("%s failed: %s" % (scene, p.stderr[-500:]))
    return (r1.ru_utime + r1.ru_stime) - (r0.ru_utime + r0.ru_stime)


def series(out, case):
    rows = list(csv.DictReader(open(os.path.join(out, case, "series.csv"))))
    dcol = [k for k in rows[0] if k.startswith("dz2/d")][0]
    return [(float(r["t"]), float(r["z2"]), float(r[dcol])) for r in rows]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexsens", default=os.path.join(ROOT, "build", "flexsens"))
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as wd:
        cpu = {s: run(a.flexsens, s, os.path.join(wd, s)) for s in ["flexible.yaml", "flexible_ancf.yaml"]}
        lines = []
        for c in CASES:
            b, e = series(os.path.join(wd, "flexible.yaml"), c), series(os.path.join(wd, "flexible_ancf.yaml"), c)
            dz = max(abs(x[1] - y[1]) for x, y in zip(b, e))
            ds = max(abs(x[2] - y[2]) for x, y in zip(b, e))
            smax = max(abs(x[2]) for x in b)
            d0 = abs(b[0][2] - e[0][2])
            lines.append("| %s | %.2e | %.2e | %.2e | %.2e |" % (c, dz, ds, smax, d0))
            print(lines[-1], flush=True)
    os.makedirs(os.path.join(ROOT, "bench", "fivebar_ancf"), exist_ok=True)
    with open(os.path.join(ROOT, "bench", "fivebar_ancf", "bench.md"), "w") as f:
        f.write("# Flexible five-bar: positions-only beam 1-2 vs ANCF cable (bench/fivebar_ancf_bench.py)\n\n"
                "Both scenes: beam 1-2 in two elements (nodes n1, n4, n2), trapezoidal rule, dt 1 ms, 5 s, "
                "frames every 10 ms. Differences are maxima over the frames.\n\n"
                "CPU (user + system, all 12 cases of a scene in one process): positions-only %.2f s, "
                "ANCF %.2f s (ratio %.2f; n = 8 vs 14 coordinates).\n\n" % (
                    cpu["flexible.yaml"], cpu["flexible_ancf.yaml"], cpu["flexible_ancf.yaml"] / cpu["flexible.yaml"]))
        f.write("| case | max abs diff z2 [m] | max abs diff dz2/dp | max abs dz2/dp (beam) | diff of dz2/dp at t = 0 |\n"
                "|---|---|---|---|---|\n")
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
