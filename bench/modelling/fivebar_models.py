#!/usr/bin/env python3
"""Modelling choices for the flexible five-bar, from one run of this script (not a test).

Each variant of examples/fivebar/flexible.yaml runs one PIM case (default F2, parameter L_A1,
trapezoidal dt 1e-3 s, 5 s) and is compared with the full model (beam 1-2 flexible, 2
segments, with mass): the largest and the final |z2 - z2_full| and |dz2/dp - full|, the steps,
the Newton iterations and the CPU time of the flexsens process (user + system, from
os.wait4). Variants: beam 1-2 rigid (the case's F-R twin), massless (inertia: none), halved
(1 segment: axial only) and doubled (4 segments). Writes bench/modelling/fivebar_models.md.

    python3 bench/modelling/fivebar_models.py [--flexsens build/flexsens] [--case F2]
"""
import argparse, csv, json, os, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "examples", "fivebar", "flexible.yaml")
BEAM = """  - name: beam_12                           # E = 206.94 GPa, square side 0.01031 m,
    type: beam                              # 7829 kg/m^3: 1.5 kg like the rigid bar
    nodes: [n1, n4, n2]
"""


def variants(text):
    base = text.replace("    directory: results/fivebar_flexible", "    directory: unused\n  vtk: false")
    assert BEAM in base, "flexible.yaml changed: update BEAM"
    mid = "  - {name: n4, position: [-0.25, -1.5]}     # midpoint of beam 1-2\n"
    assert mid in base
    # quarter points of n1 (-1, -1) -> n2 (0.5, -2)
    quarters = ("  - {name: q1, position: [-0.625, -1.25]}\n  - {name: n4, position: [-0.25, -1.5]}\n"
                "  - {name: q3, position: [0.125, -1.75]}\n")
    return {
        "full (2 segments, with mass)": (base, None),
        "rigid (F-R twin)": (base, "R"),
        "massless (inertia: none)": (base.replace(BEAM, BEAM + "    inertia: none\n").replace(
            "    density: 7829\n", ""), None),
        "halved (1 segment)": (base.replace(mid, "").replace("nodes: [n1, n4, n2]", "nodes: [n1, n2]"), None),
        "doubled (4 segments)": (base.replace(mid, quarters).replace("nodes: [n1, n4, n2]",
                                                                     "nodes: [n1, q1, n4, q3, n2]"), None),
    }


def run(exe, text, case, wd, tag):
    path = os.path.join(wd, tag + ".yaml")
    open(path, "w").write(text)
    out = os.path.join(wd, tag)
    p = subprocess.Popen([exe, "run", path, "--case", case, "--out", out],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    _, status, usage = os.wait4(p.pid, 0)
    err = p.stderr.read()
    if os.waitstatus_to_exitcode(status) != 0:
        return {"error": err.strip().splitlines()[-1] if err.strip() else "exit %d" % status}
    rows = list(csv.DictReader(open(os.path.join(out, case, "series.csv"))))
    s = json.load(open(os.path.join(out, case, "summary.json")))
    return {"t": [float(r["t"]) for r in rows], "z2": [float(r["z2"]) for r in rows],
            "dz2": [float(r[next(k for k in r if k.startswith("dz2/d"))]) for r in rows],
            "steps": s["statistics"]["steps"], "newton": s["statistics"]["newton_iterations"],
            "cpu": usage.ru_utime + usage.ru_stime, "status": s["status"]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexsens", default=os.path.join(ROOT, "build", "flexsens"))
    ap.add_argument("--case", default="F2")
    a = ap.parse_args()
    text = open(SCENE).read()
    res = {}
    with tempfile.TemporaryDirectory() as wd:
        for i, (name, (t, suffix)) in enumerate(variants(text).items()):
            res[name] = run(a.flexsens, t, a.case + (suffix or ""), wd, "v%d" % i)
    full = res["full (2 segments, with mass)"]
    lines = ["# Five-bar modelling choices (case %s, trapezoidal dt 1e-3 s, 5 s)" % a.case, "",
             "`python3 bench/modelling/fivebar_models.py --case %s`; errors against the full model "
             "(beam 1-2 flexible in 2 segments, with mass), over all frames (every 0.01 s) and at 5 s. "
             "CPU: user + system of the flexsens process on this machine; the ratio to the full "
             "model is what carries over." % a.case, "",
             "| model | steps | Newton it. | CPU [s] | CPU / full | max abs z2 err [m] | z2 err at 5 s | "
             "max abs dz2/dp err | dz2/dp err at 5 s | status |", "|---|---|---|---|---|---|---|---|---|---|"]
    for name, r in res.items():
        if "error" in r:
            lines.append("| %s | - | - | - | - | - | - | - | - | %s |" % (name, r["error"].replace("|", "/")))
            continue
        ez = [abs(x - y) for x, y in zip(r["z2"], full["z2"])]
        ed = [abs(x - y) for x, y in zip(r["dz2"], full["dz2"])]
        lines.append("| %s | %d | %d | %.3f | %.2f | %.3g | %.3g | %.3g | %.3g | %s |" % (
            name, r["steps"], r["newton"], r["cpu"], r["cpu"] / full["cpu"], max(ez), ez[-1], max(ed), ed[-1],
            r["status"]))
    rng = max(full["z2"]) - min(full["z2"])
    drng = max(full["dz2"]) - min(full["dz2"])
    lines += ["", "Range over the run of the full model: z2 %.4g m, dz2/dp %.4g." % (rng, drng)]
    out = os.path.join(ROOT, "bench", "modelling", "fivebar_models.md")
    open(out, "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
