#!/usr/bin/env python3
"""Issue #11's speed-up on the satellite (not a test): the 10-s deployment, BDF-1 dt 0.02 s, at
n = 495, with no parameter and with SAT1's one (its PIM case), run by an older flexsens binary
(the algorithm before the saddle-point LU: build commit aa5cc33 into a worktree) and by this
one with full and with modified Newton, all in one run. Writes bench/satellite/speedup.md.

    python3 bench/satellite/speedup.py --old /path/to/old/flexsens [--flexsens build/flexsens] [--repeat 3]
"""
import argparse, json, os, subprocess, tempfile, time

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "examples", "satellite", "satellite.yaml")
ap = argparse.ArgumentParser()
ap.add_argument("--old", required=True)
ap.add_argument("--flexsens", default=os.path.join(ROOT, "build", "flexsens"))
ap.add_argument("--repeat", type=int, default=3)
a = ap.parse_args()
tmp = tempfile.mkdtemp(prefix="sat_speedup_")

# The scene without parameters and cases (next to the original: its mesh path is relative).
doc = yaml.safe_load(open(SCENE))
doc.pop("parameters", None)
doc.pop("cases", None)
doc.setdefault("output", {})["vtk"] = False
plain = os.path.join(os.path.dirname(SCENE), ".speedup_plain.yaml")
yaml.safe_dump(doc, open(plain, "w"), sort_keys=False)
doc1 = yaml.safe_load(open(SCENE))
doc1.setdefault("output", {})["vtk"] = False
withp = os.path.join(os.path.dirname(SCENE), ".speedup_sat1.yaml")
yaml.safe_dump(doc1, open(withp, "w"), sort_keys=False)


def run(exe, scene, case, newton):
    out = os.path.join(tmp, "out")
    cmd = [exe, "run", scene, "--integrator", "bdf1", "--out", out] + (["--case", case] if case else [])
    if newton:
        cmd += ["--newton", newton]
    best = integ = None
    for _ in range(a.repeat):
        t0 = time.perf_counter()
        r = subprocess.run(cmd, capture_output=True, text=True)
        dt = time.perf_counter() - t0
        if r.returncode not in (0, 5):
            raise SystemExit("run failed: %s\n%s" % (" ".join(cmd), r.stderr))
        best = dt if best is None else min(best, dt)
        s = json.load(open(os.path.join(out, case, "summary.json") if case else os.path.join(out, "summary.json")))
        integ = s["wall_time_s"] if integ is None else min(integ, s["wall_time_s"])
    return s, best, integ


rows = []
try:
    for label, scene, case in [("no parameter", plain, None), ("SAT1 (1 parameter)", withp, "SAT1")]:
        base = ibase = None
        for name, exe, newton in [("before (aa5cc33, full Newton, KLU AMD)", a.old, "full"),
                                  ("now, full Newton", a.flexsens, "full"),
                                  ("now, modified Newton", a.flexsens, "modified")]:
            s, wall, integ = run(exe, scene, case, newton)
            st = s["statistics"]
            base = base or wall
            ibase = ibase or integ
            rows.append((label, name, wall, base / wall, integ, ibase / integ, st["steps"], st["factorizations"] / st["steps"],
                         st.get("lu_fill", float("nan")), st.get("factorization_seconds", float("nan")),
                         s["status"]))
finally:
    os.remove(plain)
    os.remove(withp)

nominal = {(r[0] == "no parameter", r[1]): r[2] for r in rows}
with open(os.path.join(ROOT, "bench", "satellite", "speedup.md"), "w") as f:
    f.write("# Satellite 10-s deployment: before and after the saddle-point LU (issue #11)\n\n")
    f.write("`python3 bench/satellite/speedup.py --old OLD` (%s, %d cores); process wall time, best of %d; "
            "BDF-1 dt 0.02 s, n = 495, m = 105, VTK off. 'x faster' against the old binary in the same "
            "model row group; 'integration' is summary.json's wall_time_s (the time integration alone, "
            "without start-up, scene reading, meshing and output), best of the same runs.\n\n"
            % (time.strftime("%Y-%m-%d"), os.cpu_count(), a.repeat))
    f.write("| model | algorithm | wall [s] | x faster | integration [s] | x faster (integration) | steps | "
            "factorizations / step | lu_fill | factorization [s] | status |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|\n")
    for r in rows:
        f.write("| %s | %s | %.2f | %.1f | %.3f | %.1f | %d | %.2f | %.2f | %.3f | %s |\n" % r)
    f.write("\nSensitivity overhead, cost(SAT1 with its parameter) / cost(no parameter), same algorithm "
            "(the parameter run also does its PIM start):\n\n")
    for name in sorted({r[1] for r in rows}):
        f.write("- %s: %.2f\n" % (name, nominal[(False, name)] / nominal[(True, name)]))
print(open(os.path.join(ROOT, "bench", "satellite", "speedup.md")).read())
