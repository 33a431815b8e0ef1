#!/usr/bin/env python3
"""Flexible five-bar: beam 1-2 as a positions-only beam (examples/fivebar/flexible.yaml) and as
ANCF cable elements (flexible_ancf.yaml), every case F1-F6 and F1R-F6R, 5 s of the scenes'
trapezoidal rule (dt 1 ms). How far apart are z2 and dz2/dp, and at what CPU cost (not a test).
Reference: the same scene with beam 1-2 as 8 ANCF elements (also shown: the positions-only beam
with 16 segments), so each two-element model's own error is stated.

    python3 bench/fivebar_ancf_bench.py [--flexsens build/flexsens]
Writes bench/fivebar_ancf/bench.md.
"""
import argparse, csv, os, resource, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CASES = ["F%d" % i for i in range(1, 7)] + ["F%dR" % i for i in range(1, 7)]


def refined(scene, n, wd):
    """The scene with beam 1-2 in n elements: nodes m1 .. m(n-1) between n1 (-1, -1) and n2 (0.5, -2)."""
    text = open(os.path.join(ROOT, "examples", "fivebar", scene)).read()
    nodes = "".join("  - {name: m%d, position: [%.17g, %.17g]}\n" % (i, -1 + 1.5 * i / n, -1 - i / n) for i in range(1, n))
    old = "  - {name: n4, position: [-0.25, -1.5]}     # midpoint of beam 1-2\n"
    assert old in text
    text = text.replace(old, nodes).replace("nodes: [n1, n4, n2]",
                                            "nodes: [n1, %s, n2]" % ", ".join("m%d" % i for i in range(1, n)))
    path = os.path.join(wd, "%s_%d.yaml" % (scene[:-5], n))
    open(path, "w").write(text)
    return path


def run(exe, scene, out):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run([exe, "run", scene if os.path.isabs(scene) else os.path.join(ROOT, "examples", "fivebar", scene),
                        "--out", out],
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
        for s, n in [("flexible_ancf.yaml", 8), ("flexible.yaml", 16)]:
            cpu["%s_%d" % (s, n)] = run(a.flexsens, refined(s, n, wd), os.path.join(wd, "%s_%d" % (s, n)))
        lines = []
        for c in CASES:
            b, e = series(os.path.join(wd, "flexible.yaml"), c), series(os.path.join(wd, "flexible_ancf.yaml"), c)
            ref = series(os.path.join(wd, "flexible_ancf.yaml_8"), c)
            b16 = series(os.path.join(wd, "flexible.yaml_16"), c)
            dist = lambda u, w, k: max(abs(x[k] - y[k]) for x, y in zip(u, w))
            smax = max(abs(x[2]) for x in ref)
            lines.append("| %s | %.2e | %.2e | %.2e | %.2e | %.2e | %.2e | %.2e | %.2e |" % (
                c, dist(b, e, 1), dist(b, e, 2), dist(b, ref, 1), dist(e, ref, 1), dist(b16, ref, 1),
                dist(b, ref, 2), dist(e, ref, 2), smax))
            print(lines[-1], flush=True)
    os.makedirs(os.path.join(ROOT, "bench", "fivebar_ancf"), exist_ok=True)
    with open(os.path.join(ROOT, "bench", "fivebar_ancf", "bench.md"), "w") as f:
        f.write("# Flexible five-bar: positions-only beam 1-2 vs ANCF cable (bench/fivebar_ancf_bench.py)\n\n"
                "Both scenes: beam 1-2 in two elements (nodes n1, n4, n2), trapezoidal rule, dt 1 ms, 5 s, "
                "frames every 10 ms. Differences are maxima over the frames.\n\n"
                "CPU (user + system, all 12 cases of a scene in one process): positions-only %.2f s, "
                "ANCF %.2f s (ratio %.2f; n = 8 vs 14 coordinates); reference ANCF N = 8: %.2f s; "
                "positions-only N = 16: %.2f s.\n\n" % (
                    cpu["flexible.yaml"], cpu["flexible_ancf.yaml"], cpu["flexible_ancf.yaml"] / cpu["flexible.yaml"],
                    cpu["flexible_ancf.yaml_8"], cpu["flexible.yaml_16"]))
        f.write("Columns: beam = positions-only, 2 segments; ancf = 2 ANCF elements; ref = 8 ANCF elements; "
                "b16 = positions-only, 16 segments. s = dz2/dp. All maxima over t in [0, 5] s.\n\n")
        f.write("| case | z2 beam-ancf [m] | s beam-ancf | z2 beam-ref | z2 ancf-ref | z2 b16-ref | s beam-ref | "
                "s ancf-ref | max abs s (ref) |\n|---|---|---|---|---|---|---|---|---|\n")
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
