#!/usr/bin/env python3
"""Satellite: panel beams and springs as positions-only beams (examples/satellite/satellite.yaml)
and as ANCF cables (satellite_ancf.yaml), cases SAT1 and SAT2 (not a test; issue 15 item 3).
How far apart are x_B2, the four opening angles and dx_B2/dL_B1B2, and at what cost.

Runs (each scene as written, and with every panel and spring segment count doubled, so each
model's own discretization error is stated next to the difference between the models):
  - the paper's BDF-1, dt 0.02 s, 10 s (it dissipates ~95% of the energy: both models are
    compared under the same heavy numerical damping);
  - generalized-alpha, rho_inf 0.5, dt 1 ms, the first --ga-time seconds (little damping of
    the panels' motion), the scenes as written only.
CPU = user + system of the flexsens process (getrusage of the child), both cases in one process.

    python3 bench/satellite_ancf_bench.py [--flexsens build/flexsens] [--ga-time 2]
Writes bench/satellite_ancf/bench.md.
"""
import argparse, csv, json, os, resource, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SAT = os.path.join(ROOT, "examples", "satellite")
CASES = ["SAT1", "SAT2"]
OUTS = ["xB2", "open1", "open2", "open3", "open4", "dxB2/dL_B1B2"]


def variant(scene, doubled, wd):
    """The scene (copied beside its geometry's relative path) with panel and spring segments doubled."""
    text = open(os.path.join(SAT, scene)).read()
    if doubled:
        assert "segments: 20" in text and "segments: 10" in text
        text = text.replace("segments: 20", "segments: 40").replace("segments: 10", "segments: 20")
    path = os.path.join(SAT, ".bench_%s_%d_%d.yaml" % (scene[:-5], doubled, os.getpid()))
    open(path, "w").write(text)  # beside the original: its geometry path is relative
    return path


def run(exe, scene, out, extra):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run([exe, "run", scene, "--out", out] + extra, capture_output=True, text=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode not in (0, 5):  # 5: suspect (BDF-1's energy loss), the run itself completed
        sys.exit("%s failed: %s" % (scene, p.stderr[-800:]))
    stats = {c: json.load(open(os.path.join(out, c, "summary.json"))) for c in CASES}
    return (r1.ru_utime + r1.ru_stime) - (r0.ru_utime + r0.ru_stime), stats


def series(out, case):
    rows = list(csv.DictReader(open(os.path.join(out, case, "series.csv"))))
    return [[float(r["t"])] + [float(r[k]) for k in OUTS] for r in rows]


def dist(u, w, k):
    assert len(u) == len(w) and all(abs(a[0] - b[0]) < 1e-9 for a, b in zip(u, w))
    return max(abs(a[k] - b[k]) for a, b in zip(u, w))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexsens", default=os.path.join(ROOT, "build", "flexsens"))
    ap.add_argument("--ga-time", type=float, default=2.0)
    a = ap.parse_args()
    res, made = {}, []
    try:
        with tempfile.TemporaryDirectory() as wd:
            for scene in ["satellite.yaml", "satellite_ancf.yaml"]:
                for doubled in [0, 1]:
                    path = variant(scene, doubled, wd)
                    made.append(path)
                    key = (scene, doubled, "bdf1")
                    out = os.path.join(wd, "%s_%d_bdf1" % (scene, doubled))
                    cpu, st = run(a.flexsens, path, out, [])
                    res[key] = (cpu, st, {c: series(out, c) for c in CASES})
                    print(key, "cpu %.1f s" % cpu, flush=True)
                key = (scene, 0, "ga")
                out = os.path.join(wd, "%s_0_ga" % scene)
                cpu, st = run(a.flexsens, os.path.join(SAT, scene), out,
                              ["--integrator", "generalized_alpha", "--dt", "0.001", "--t-end", str(a.ga_time)])
                res[key] = (cpu, st, {c: series(out, c) for c in CASES})
                print(key, "cpu %.1f s" % cpu, flush=True)
    finally:
        for p in made:
            os.remove(p)
    P, A = "satellite.yaml", "satellite_ancf.yaml"
    lines = ["# Satellite: positions-only beams vs ANCF cables (bench/satellite_ancf_bench.py)\n",
             "Panel beams (10 segments of 1 m) and springs (20 segments, straight at rest, bent into "
             "270-degree arcs) as positions-only beams (`satellite.yaml`) or ANCF cables "
             "(`satellite_ancf.yaml`: pins between ANCF chains as separate nodes, see the scene). "
             "'x2' = every panel and spring segment count doubled. Angles in rad, x_B2 in m; "
             "s = dx_B2/dL_B1B2. Differences are maxima over the frames (every 0.1 s).\n"]
    lines.append("## Cost (both cases in one process)\n")
    lines.append("| model | integrator | n | steps per case | Newton iterations per step | fill nnz(L+U)/nnz(A) | "
                 "factorization s per case | CPU s (process) |\n|---|---|---|---|---|---|---|---|")
    for key in sorted(res, key=lambda k: (k[2], k[0], k[1])):
        cpu, st, _ = res[key]
        s = st["SAT1"]
        lines.append("| %s%s | %s | %d | %d | %.2f | %.2f | %.2f | %.1f |" % (
            key[0][:-5], " x2" if key[1] else "", key[2] if key[2] == "bdf1" else "GA rho 0.5, %g s" % a.ga_time,
            s["n"], s["statistics"]["steps"], s["statistics"]["newton_iterations"] / s["statistics"]["steps"],
            s["statistics"]["lu_fill"], s["statistics"]["factorization_seconds"], cpu))
    for integ, title in [("bdf1", "BDF-1, dt 0.02 s, 10 s"), ("ga", "generalized-alpha rho_inf 0.5, dt 1 ms, %g s" % a.ga_time)]:
        lines.append("\n## Differences, %s\n" % title)
        hdr = ["x_B2", "open1", "open2", "open3", "open4", "s"]
        pairs = [("beam - ANCF", (P, 0), (A, 0))]
        if integ == "bdf1":
            pairs += [("beam - beam x2", (P, 0), (P, 1)), ("ANCF - ANCF x2", (A, 0), (A, 1)),
                      ("beam x2 - ANCF x2", (P, 1), (A, 1))]
        lines.append("| case | pair | " + " | ".join(hdr) + " | max abs x_B2 | max abs s |\n|" + "---|" * (len(hdr) + 4))
        for c in CASES:
            for label, u, w in pairs:
                su, sw = res[(u[0], u[1], integ)][2][c], res[(w[0], w[1], integ)][2][c]
                lines.append("| %s | %s | %s | %.3g | %.3g |" % (
                    c, label, " | ".join("%.2e" % dist(su, sw, k) for k in range(1, 7)),
                    max(abs(r[1]) for r in sw), max(abs(r[6]) for r in sw)))
    os.makedirs(os.path.join(ROOT, "bench", "satellite_ancf"), exist_ok=True)
    with open(os.path.join(ROOT, "bench", "satellite_ancf", "bench.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
