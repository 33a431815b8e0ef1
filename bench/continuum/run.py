#!/usr/bin/env python3
"""Meshed bodies refined towards n ~ 50k (not a test): the solid pendulum (P2 neo-Hookean
tetrahedra) and the shell panel, the scenes of bench/scaling/run.py (10 steps), with 0, 1 and 2
whole-body parameters (E, density / thickness, E: what one meshed body offers) under modified
Newton (the meshed bodies' default) and without parameters under full Newton (up to n ~ 25k;
beyond, its factorization per iteration takes minutes). Per run: n, steps, Newton iterations,
factorizations, the factorization's share of the integration (factorization_seconds /
wall_time_s), fill nnz(L)/nnz(A), the cost per step and coordinate, peak RSS of the process.
Writes bench/continuum/results.md, results.csv and cost.png (log-log).

    python3 bench/continuum/run.py [--flexsens build/flexsens] [--quick]
"""
import argparse, csv, importlib.util, json, os, shutil, subprocess, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "bench", "continuum")
spec = importlib.util.spec_from_file_location("scaling", os.path.join(ROOT, "bench", "scaling", "run.py"))
scaling = importlib.util.module_from_spec(spec)
spec.loader.exec_module(scaling)

MODELS = {  # name: scene generator, geometry file, element sizes [m], largest size full Newton runs at
    "solid pendulum": (scaling.solid_scene, "examples/solid/pendulum3d.geo", (0.04, 0.02, 0.014, 0.01, 0.008), 0.01),
    "shell panel": (scaling.panel_scene, "examples/shell/panel.geo", (0.0065, 0.004, 0.0025, 0.0017, 0.0012), 0.0017),
}
QUICK = {"solid pendulum": (0.04, 0.02), "shell panel": (0.0065, 0.004)}


def run(exe, scene, wd, newton):
    out = os.path.join(wd, "out")
    shutil.rmtree(out, ignore_errors=True)
    p = subprocess.run(["/usr/bin/time", "-f", "%M", exe, "run", scene, "--out", out, "--newton", newton],
                       capture_output=True, text=True)
    rss = int(p.stderr.strip().splitlines()[-1])
    if p.returncode not in (0, 5):
        return None, p.stderr.strip().splitlines()[0]
    s = json.load(open(os.path.join(out, "summary.json")))
    return (s, rss), None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexsens", default=os.path.join(ROOT, "build", "flexsens"))
    ap.add_argument("--quick", action="store_true")
    a = ap.parse_args()
    exe = os.path.abspath(a.flexsens)
    rows = []
    with tempfile.TemporaryDirectory() as wd:
        for model, (make, geo, sizes, fullUpTo) in MODELS.items():
            shutil.copy(os.path.join(ROOT, geo), wd)
            for size in (QUICK[model] if a.quick else sizes):
                for newton, nparams in (("modified", 0), ("modified", 1), ("modified", 2), ("full", 0)):
                    if newton == "full" and size < fullUpTo:
                        continue
                    scene = os.path.join(wd, "scene.yaml")
                    open(scene, "w").write(make(size, nparams))
                    res, err = run(exe, scene, wd, newton)
                    if not res:
                        rows.append((model, size, newton, nparams, None, err))
                        print(rows[-1], flush=True)
                        continue
                    s, rss = res
                    st = s["statistics"]
                    n = s["n"] if "n" in s else st.get("n")
                    w = s["wall_time_s"]
                    rows.append((model, size, newton, nparams, dict(n=n, steps=st["steps"], it=st["newton_iterations"],
                                 fact=st["factorizations"], fshare=st.get("factorization_seconds", 0.0) / w,
                                 fill=st.get("lu_fill", float("nan")), wall=w, us=1e6 * w / st["steps"] / n, rss=rss / 1024,
                                 status=s["status"]), None))
                    print(rows[-1], flush=True)
    write(rows, a.quick)


def write(rows, quick):
    ok = [r for r in rows if r[4]]
    with open(os.path.join(OUT, "results.csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["model", "size_m", "newton", "parameters", "n", "steps", "newton_iterations", "factorizations",
                    "factorization_share", "fill", "wall_s", "us_per_step_coord", "rss_MB", "status"])
        for m, size, newton, npar, d, _ in ok:
            w.writerow([m, size, newton, npar, d["n"], d["steps"], d["it"], d["fact"], "%.3f" % d["fshare"],
                        "%.2f" % d["fill"], "%.3f" % d["wall"], "%.2f" % d["us"], "%.0f" % d["rss"], d["status"]])
    md = ["# Meshed bodies towards n ~ 50k", "",
          "Written by `python3 bench/continuum/run.py`%s: the scenes of bench/scaling/run.py (10 steps each), on"
          % (" --quick" if quick else ""),
          "the 2-core machine (times are one run each; the counters do not depend on the machine).",
          "Cost = wall_time_s of summary.json (the integration) / steps / n; factorization share = its",
          "factorization_seconds / wall_time_s; fill = lu_fill of summary.json (the factor's nonzeros over the matrix's); RSS = peak of the whole process.",
          "Parameters: the whole body's E and density (solid) or thickness and E (shell): one meshed body has",
          "no more whole-body parameters; per-element families are the adjoint's (bench/adjoint).", "",
          "![cost per step and coordinate](cost.png)", "",
          "| model | element size [m] | Newton | parameters | n | Newton iterations | factorizations | factorization share | fill | wall [s] | us / step / coordinate | RSS [MB] | status |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for m, size, newton, npar, d, err in rows:
        if d:
            md.append("| %s | %g | %s | %d | %d | %d | %d | %.2f | %.2f | %.2f | %.2f | %.0f | %s |" % (
                m, size, newton, npar, d["n"], d["it"], d["fact"], d["fshare"], d["fill"], d["wall"], d["us"], d["rss"], d["status"]))
        else:
            md.append("| %s | %g | %s | %d | failed: %s | | | | | | | | |" % (m, size, newton, npar, err))
    md.append("")
    for model in MODELS:
        base = [r for r in ok if r[0] == model and r[2] == "modified" and r[3] == 0]
        if len(base) >= 2:
            lo, hi = min(base, key=lambda r: r[4]["n"]), max(base, key=lambda r: r[4]["n"])
            md.append("- %s, modified Newton, no parameters: cost per step and coordinate %.1f us at n = %d, %.1f us at "
                      "n = %d (%.2fx)" % (model, lo[4]["us"], lo[4]["n"], hi[4]["us"], hi[4]["n"], hi[4]["us"] / lo[4]["us"]))
    open(os.path.join(OUT, "results.md"), "w").write("\n".join(md) + "\n")
    plot(ok)
    print("\n".join(md))


def plot(ok):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for model in MODELS:
        for newton, npar, style in (("modified", 0, "o-"), ("modified", 2, "s--"), ("full", 0, "^:")):
            r = sorted((x for x in ok if x[0] == model and x[2] == newton and x[3] == npar), key=lambda x: x[4]["n"])
            if r:
                ax.plot([x[4]["n"] for x in r], [x[4]["us"] for x in r], style,
                        label="%s, %s Newton, %d parameters" % (model, newton, npar))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("coordinates n")
    ax.set_ylabel("integration cost per step and coordinate [us]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "cost.png"), dpi=110)


if __name__ == "__main__":
    main()
