#!/usr/bin/env python3
"""Full vs modified Newton (integrator.newton) with BDF-1: satellite SAT1 over 2 s (dt 0.02)
and the flexible five-bar F1 over 1 s (dt 1e-3), each with its one parameter (the PIM case)
and with none (the scene without `parameters` and `cases`: initial state from the scene's
positions and velocities, so the motion differs a little from the case's). Prints a markdown
table of the counters from summary.json and the wall time of the process (best of --repeat).

usage: bench/newton/run.py [--flexsens build/flexsens] [--repeat 3]
"""
import argparse, json, os, subprocess, tempfile, time, yaml

ap = argparse.ArgumentParser()
ap.add_argument("--flexsens", default="build/flexsens")
ap.add_argument("--repeat", type=int, default=3)
args = ap.parse_args()
tmp = tempfile.mkdtemp(prefix="bench_newton_")

MODELS = [  # name, scene, case, t_end
    ("satellite SAT1", "examples/satellite/satellite.yaml", "SAT1", 2.0),
    ("flexible five-bar F1", "examples/fivebar/flexible.yaml", "F1", 1.0),
]

def without_parameters(scene):
    doc = yaml.safe_load(open(scene))
    doc.pop("parameters", None)
    doc.pop("cases", None)
    # Mesh files and tables are resolved next to the scene: keep it beside the original.
    path = os.path.join(os.path.dirname(scene), ".bench_noparam_" + os.path.basename(scene))
    yaml.safe_dump(doc, open(path, "w"), sort_keys=False)
    return path

def run(scene, case, t_end, newton):
    out = os.path.join(tmp, "run")
    cmd = [args.flexsens, "run", scene, "--integrator", "bdf1", "--t-end", str(t_end), "--newton", newton, "--out", out]
    if case:
        cmd += ["--case", case]
    best = None
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)  # exit 5 (suspect) is fine
        dt = time.perf_counter() - t0
        best = dt if best is None else min(best, dt)
    summary = json.load(open(os.path.join(out, case, "summary.json") if case else os.path.join(out, "summary.json")))
    return summary["statistics"], best

rows = []
for name, scene, case, t_end in MODELS:
    plain = without_parameters(scene)
    try:
        res = {}
        for newton in ("full", "modified"):
            for npar, (sc, cs) in ((0, (plain, None)), (1, (scene, case))):
                res[newton, npar] = run(sc, cs, t_end, newton)
    finally:
        os.remove(plain)
    base = res["full", 0][1]
    for newton in ("full", "modified"):
        for npar in (0, 1):
            st, wall = res[newton, npar]
            steps = st["steps"]
            overhead = res[newton, 1][1] / res[newton, 0][1]
            rows.append(f"| {name} | {newton} | {npar} | {steps} | {st['newton_iterations'] / steps:.2f} | "
                        f"{st['factorizations'] / steps:.3f} | {st['sensitivity_iterations'] / steps:.2f} | "
                        f"{st['sensitivity_factorizations']} | {st['convergence_failures']} | {wall:.3f} | "
                        f"{wall / base:.2f} | {overhead:.2f} |")

print("| model | newton | parameters | steps | Newton iterations / step | factorizations / step | "
      "sensitivity GMRES solves / step | sensitivity factorizations | steps redone (full Newton) | "
      "wall [s] | wall / full, 0 parameters | cost(1 dd) / cost(0) |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
print("\n".join(rows))
