#!/usr/bin/python3
"""Meshed bodies refined to n ~ 100k (not a test): cost per coordinate, factorization share,
fill and peak RSS of three models, each with 0, 1 and 10 parameters:

  solid       the solid pendulum (examples/solid/pendulum3d.yaml, P2 neo-Hookean tetrahedra),
              trapezoidal, 10 steps of 5 ms, n 1.7k ... 97k;
  panel       the shell panel (examples/shell/panel.yaml without cases), trapezoidal, 10 steps
              of 1 ms, n 1.8k ... 97k;
  cantilever  `flexsens static` of the 3D cantilever of bench/solid_cantilever_bench.py (P2
              tetrahedra, steel, root face fixed, 100 N on the tip face) under its own weight
              too, one load step, n 1.3k ... 95k, its tip deflection against Timoshenko's.

The dynamic models run under modified Newton at every size and under full Newton up to n ~ 25k
(beyond, one factorization per iteration costs minutes); `flexsens static` is full Newton.
Scenes: bench/scaling/run.py's solid_scene and panel_scene (with a zero point force at the tip in
every run, so 0, 1 and 10 parameters integrate the same model) and
bench/solid_cantilever_bench.py's scene with gravity and a 1 N axial pull at the tip centre.

One flexsens process per row: its summary.json gives the counters and the solve's wall time,
/usr/bin/time the peak RSS and the process's CPU time, /proc/stat the CPU the rest of the
machine used meanwhile. At the end the largest solid pendulum with ten parameters runs once more
under `perf record -F 499 -g` for its top five functions.

    bench/continuum/run.py [--flexsens build/flexsens] [--quick] [--models solid,panel,cantilever]
        [--params 0,1,10] [--newton modified,full] [--sizes H,...] [--no-perf] [--time-limit S] [--out DIR]
        [--report-only]

It writes results.md, results.csv, cost.png and meta.json (commands, commits, the profile) here; a run of some models,
sizes, parameter counts or Newton variants keeps the other rows of the existing results.csv.
--quick runs the two smallest sizes of each model into a fresh temporary directory.
Needs /usr/bin/python3 (python3-matplotlib), /usr/bin/time and perf.
"""
import argparse, csv, importlib.util, json, os, re, shutil, signal, subprocess, sys, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.dont_write_bytecode = True  # importing the generators must not leave __pycache__ in bench/
sys.path.insert(0, os.path.join(ROOT, "bench"))
import solid_cantilever_bench as cantilever  # noqa: E402  (scene(), timoshenko(), E)

_spec = importlib.util.spec_from_file_location("scaling_run", os.path.join(ROOT, "bench", "scaling", "run.py"))
scaling = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(scaling)

PARAM_COUNTS = (0, 1, 10)
FULL_NEWTON_UP_TO = 25000  # [coordinates] full Newton runs at the sizes up to this n (about)
SHARED_CORES = 0.2         # other processes' CPU [cores] during a row above which it is "shared"

# ---------------------------------------------------------------------------------------------
# The static cantilever: bench/solid_cantilever_bench.py's 3D bar (L = 1 m, 0.1 m square, steel,
# nu = 0, root face fixed, P = 100 N spread over the tip face), plus gravity and a 1 N axial pull
# at the tip centre so that ten distinct parameters have an effect.

CANT_P = 100.0      # [N] the tip face's total load, -y
CANT_G = 9.81       # [m/s^2] gravity, -y
CANT_RHO = 7800.0   # [kg/m^3] the scene's density
CANT_L, CANT_B, CANT_H = 1.0, 0.1, 0.1  # [m]
CANT_PARAMS = [("E", "body", "E"), ("nu", "body", "nu"), ("density", "body", "density"),
               ("g_x", "gravity", "x"), ("g_y", "gravity", "y"), ("g_z", "gravity", "z"),
               ("F_x", "tip_load", "x"), ("F_y", "tip_load", "y"), ("F_z", "tip_load", "z"),
               ("F_scale", "tip_load", "value")]


def cantilever_scene(size, nparams):
    text = cantilever.scene(3, size, 2, CANT_P).replace(cantilever.GEO + "/", "")  # the .geo beside the scene
    text, k1 = re.subn(r"^dimension: 3\n", "dimension: 3\ngravity: [0, %g, 0]\n" % -CANT_G, text, flags=re.M)
    text, k2 = re.subn(r"\nstatic:", "\n  - {name: tip_load, type: point_force, node: tipmid, force: [1, 0, 0],"
                       " function: {type: constant, value: 1}}\nstatic:", text)
    if (k1, k2) != (1, 1):
        sys.exit("continuum bench: bench/solid_cantilever_bench.py's scene changed, the cantilever no longer fits")
    return text + scaling.parameter_lines(CANT_PARAMS, nparams)


def timoshenko_tip():
    """Timoshenko beam (kappa = 5/6, nu = 0) under the tip load and the uniform weight
    w = rho g A: P L^3/(3EI) + P L/(kappa G A) + w L^4/(8EI) + w L^2/(2 kappa G A) [m]. The 1 N
    axial pull does not bend it."""
    E, A, I = cantilever.E, CANT_B * CANT_H, CANT_B * CANT_H ** 3 / 12
    kGA = 5.0 / 6.0 * E / 2.0 * A
    w = CANT_RHO * CANT_G * A
    return cantilever.timoshenko(CANT_P, CANT_B, CANT_H) + w * CANT_L ** 4 / (8 * E * I) + w * CANT_L ** 2 / (2 * kGA)


MODELS = {
    "solid": dict(title="solid pendulum", kind="run", files=["examples/solid/pendulum3d.geo"],
                  make=lambda h, p: scaling.solid_scene(h, p, tip_load=True),
                  sizes=(0.04, 0.02, 0.014, 0.01, 0.0075, 0.0058), quick=(0.04, 0.02),
                  setup="examples/solid/pendulum3d.yaml at element size h (P2 neo-Hookean tetrahedra, E 2 MPa), "
                        "trapezoidal, dt %g s, %d steps, a zero point force `tip_load` at the tip node"
                        % (scaling.SOLID_DT, scaling.SOLID_STEPS),
                  params=scaling.SOLID_PARAMS_10),
    "panel": dict(title="shell panel", kind="run", files=["examples/shell/panel.geo"],
                  make=lambda h, p: scaling.panel_scene(h, p, tip_load=True),
                  sizes=(0.0065, 0.004, 0.0025, 0.0017, 0.0012, 0.00085), quick=(0.0065, 0.004),
                  setup="examples/shell/panel.yaml without PIM cases at element size h (discrete shell, hinges), "
                        "trapezoidal, dt %g s, %d steps, a zero point force `tip_load` at the tip corner"
                        % (scaling.PANEL_DT, scaling.PANEL_STEPS),
                  params=scaling.PANEL_PARAMS_10),
    "cantilever": dict(title="static cantilever", kind="static", files=["tests/scenes/solid/bar3d.geo"],
                       make=cantilever_scene, sizes=(0.1, 0.05, 0.023, 0.017, 0.0135), quick=(0.1, 0.05),
                       setup="`flexsens static` of bench/solid_cantilever_bench.py's 3D bar (L = 1 m, 0.1 m square, "
                             "E = 2.1e11 Pa, nu = 0, P2 tetrahedra at element size h, root face fixed, %g N down on "
                             "the tip face) under its weight (g = %g m/s^2) and a 1 N axial pull at the tip centre "
                             "(`tip_load`, a constant function of value 1), one load step, full Newton (`flexsens static` has no "
                             "modified Newton)" % (CANT_P, CANT_G),
                       params=CANT_PARAMS),
}

# ---------------------------------------------------------------------------------------------
# One process: time limit, peak RSS and CPU time (/usr/bin/time), the rest of the machine's CPU.


def busy_seconds():
    """CPU seconds all cores spent busy since boot (/proc/stat: user nice system irq softirq steal)."""
    f = open("/proc/stat").readline().split()
    return sum(int(f[i]) for i in (1, 2, 3, 6, 7, 8)) / os.sysconf("SC_CLK_TCK")


def run_process(cmd, limit, log):
    """(exit code or None after the limit, peak RSS [kB], process wall [s], other processes' CPU
    [cores] meanwhile). /usr/bin/time forks the run from its own small image, so the peak RSS is
    the run's (a child of this python would inherit its high-water mark)."""
    timing = log + ".time"
    busy0, t0 = busy_seconds(), time.perf_counter()
    with open(log, "w") as f:
        p = subprocess.Popen(["/usr/bin/time", "-o", timing, "-f", "%M %U %S"] + cmd, stdout=f,
                             stderr=subprocess.STDOUT, start_new_session=True)
    try:
        p.wait(timeout=limit)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGINT)  # perf writes its data; flexsens stops after a step
        try:
            p.wait(timeout=60)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
        return None, 0, time.perf_counter() - t0, 0.0
    wall, busy = time.perf_counter() - t0, busy_seconds() - busy0
    last = open(timing).read().split("\n") if os.path.exists(timing) else []
    nums = [l.split() for l in last if re.match(r"^\d+ [\d.]+ [\d.]+$", l.strip())]
    rss_kb, cpu = (int(nums[-1][0]), float(nums[-1][1]) + float(nums[-1][2])) if nums else (0, 0.0)
    return p.returncode, rss_kb, wall, max(busy - cpu, 0.0) / wall


def command(exe, kind, scene, out, newton):
    return [exe, "run", scene, "--out", out, "--newton", newton] if kind == "run" else [exe, "static", scene, "--out", out]


def run_case(exe, model, size, newton, nparams, limit, wd, perf_data=None):
    spec = MODELS[model]
    tag = "%s_%g_%s_p%d" % (model, size, newton, nparams)
    scene, out, log = (os.path.join(wd, tag + ext) for ext in (".yaml", "", ".log"))
    open(scene, "w").write(spec["make"](size, nparams))
    for f in spec["files"]:  # a scene reads files from its own folder
        shutil.copy(os.path.join(ROOT, f), wd)
    shutil.rmtree(out, ignore_errors=True)
    cmd = command(exe, spec["kind"], scene, out, newton)
    if perf_data:
        cmd = ["perf", "record", "-F", "499", "-g", "-o", perf_data, "--"] + cmd
    code, rss_kb, process_wall, others = run_process(cmd, limit, log)
    row = dict(model=model, size=size, newton=newton, params=nparams, status="", error="", rss_mb=rss_kb / 1024.0,
               process_wall_s=process_wall, others_cores=others)
    summ = os.path.join(out, "summary.json")
    if code is None:
        row.update(status="timeout", error="killed after %g s: %s" % (limit, scaling.first_error(log)))
    elif code not in (0, 5) or not os.path.exists(summ):  # 5: complete but suspect (energy audit)
        row.update(status="failed (exit %d)" % code, error=scaling.first_error(log))
    else:
        row.update(counters(json.load(open(summ)), spec["kind"]))
        if code == 5:
            row["error"] = scaling.first_error(log)
    return row


def counters(s, kind):
    st = s.get("statistics", {})
    r = dict(status=s.get("status"), n=s["n"], wall_s=s["wall_time_s"], iterations=st.get("newton_iterations"),
             steps=st.get("steps" if kind == "run" else "load_steps"), factorizations=st.get("factorizations"),
             sens_factorizations=st.get("sensitivity_factorizations"), sens_iterations=st.get("sensitivity_iterations"),
             fill=st.get("lu_fill"),
             fact_s=st.get("factorization_seconds"))
    if kind == "static":
        r["tip_deflection_m"] = -float(s["final"]["tip_y"])  # tipmid rests on the axis, y = 0
    return r

# ---------------------------------------------------------------------------------------------
# Derived figures, the CSV (read back when only a part is rerun) and the report.

CSV_COLS = ["model", "size", "newton", "params", "status", "n", "steps", "iterations", "factorizations",
            "sens_factorizations", "sens_iterations", "fact_s", "fact_share", "fill", "wall_s", "process_wall_s", "us_per_coord",
            "cost_unit", "overhead", "rss_mb", "rss_kb_per_coord", "others_cores", "tip_deflection_m",
            "timoshenko_m", "rel_diff", "error"]
TEXT_COLS = {"model", "newton", "status", "cost_unit", "error"}


def ok(r):
    return r["status"] in ("complete", "suspect")


def derive(rows):
    plain = {(r["model"], r["size"], r["newton"]): r for r in rows if r["params"] == 0 and ok(r)}
    for r in rows:
        for k in ("fact_share", "us_per_coord", "cost_unit", "overhead", "rss_kb_per_coord", "timoshenko_m", "rel_diff"):
            r[k] = None
        if not ok(r):
            continue
        static = MODELS[r["model"]]["kind"] == "static"
        per = r["iterations"] if static else r["steps"]
        r["cost_unit"] = "Newton iteration" if static else "step"
        r["us_per_coord"] = 1e6 * r["wall_s"] / per / r["n"]
        r["fact_share"] = r["fact_s"] / r["wall_s"] if r.get("fact_s") is not None else None
        r["rss_kb_per_coord"] = r["rss_mb"] * 1024 / r["n"]
        b = plain.get((r["model"], r["size"], r["newton"]))
        r["overhead"] = r["wall_s"] / b["wall_s"] if b else None
        if static:
            r["timoshenko_m"] = timoshenko_tip()
            r["rel_diff"] = r["tip_deflection_m"] / r["timoshenko_m"] - 1


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(CSV_COLS)
        for r in rows:
            w.writerow(["" if r.get(c) is None else r[c] for c in CSV_COLS])


def read_csv(path):
    rows = []
    if not os.path.exists(path):
        return rows
    for rec in csv.DictReader(open(path)):
        if set(rec) != set(CSV_COLS):
            return []  # an older layout: nothing to keep
        r = {}
        for c, v in rec.items():
            r[c] = v if c in TEXT_COLS else (None if v == "" else float(v))
        for c in ("params", "n", "steps", "iterations", "factorizations", "sens_factorizations", "sens_iterations"):
            r[c] = None if r[c] is None else int(r[c])
        rows.append(r)
    return rows


def fmt(v, spec="%.3g"):
    return "-" if v is None else spec % v


def sort_key(r):
    return (list(MODELS).index(r["model"]), -r["size"], r["newton"] != "modified", r["params"])


def near(rows, target):
    """The row whose n is nearest target (log scale)."""
    return min(rows, key=lambda r: abs(r["n"] / target - 1) if r["n"] >= target else abs(target / r["n"] - 1))


def growth_lines(mr):
    out = []
    for newton in ("modified", "full"):
        for p in PARAM_COUNTS:
            s = sorted((r for r in mr if ok(r) and r["newton"] == newton and r["params"] == p), key=lambda r: r["n"])
            if len(s) < 2:
                continue
            lo, mid, hi = s[0], near(s[1:], 25000), s[-1]
            text = "%s Newton, %d par.: %.2f us at n = %d, %.2f at n = %d (%.2fx)" % (
                newton, p, lo["us_per_coord"], lo["n"], mid["us_per_coord"], mid["n"], mid["us_per_coord"] / lo["us_per_coord"])
            if hi is not mid:
                text += ", %.2f at n = %d (%.2fx)" % (hi["us_per_coord"], hi["n"], hi["us_per_coord"] / lo["us_per_coord"])
            out.append("- cost per %s and coordinate, %s" % (s[0]["cost_unit"], text))
    return out


def ratio_list(mr, what, pick):
    """'h: ratio' over the sizes for which pick(r) gives one."""
    vals = ["n = %d: %.2f" % (r["n"], pick(r)) for r in sorted(mr, key=lambda r: r["n"]) if ok(r) and pick(r)]
    return "- %s: %s" % (what, ", ".join(vals) if vals else "no sizes")


def summary_lines(mr, kind):
    by = {(r["size"], r["newton"], r["params"]): r for r in mr if ok(r)}
    out = growth_lines(mr)
    for newton in (("modified", "full") if kind == "run" else ("full",)):
        for p in (1, 10):
            out.append(ratio_list([r for r in mr if r["newton"] == newton and r["params"] == p],
                                  "%s Newton, cost(%d par.) / cost(0)" % (newton, p), lambda r: r["overhead"]))
    for p in (PARAM_COUNTS if kind == "run" else ()):
        out.append(ratio_list([r for r in mr if r["newton"] == "full" and r["params"] == p],
                              "cost of full / modified Newton, %d par." % p,
                              lambda r: r["wall_s"] / by[(r["size"], "modified", r["params"])]["wall_s"]
                              if (r["size"], "modified", r["params"]) in by else None))
    main = [r for r in mr if ok(r) and r["newton"] == ("modified" if kind == "run" else "full")]
    for p in (0, 10):
        s = sorted((r for r in main if r["params"] == p and r["fact_share"] is not None), key=lambda r: r["n"])
        if s:
            out.append("- factorization share, %d par.: %.2f ... %.2f; at n = %d: %.2f; fill at n = %d: %.2f" % (
                p, min(r["fact_share"] for r in s), max(r["fact_share"] for r in s), s[-1]["n"], s[-1]["fact_share"],
                s[-1]["n"], s[-1]["fill"]))
    for p in (0, 10):
        s = sorted((r for r in main if r["params"] == p), key=lambda r: r["n"])
        if len(s) >= 2:
            out.append("- peak RSS, %d par.: %.0f MB at n = %d (%.1f kB per coordinate), %.0f MB at n = %d (%.1f kB); "
                       "%.1f kB per added coordinate" % (p, s[0]["rss_mb"], s[0]["n"], s[0]["rss_kb_per_coord"],
                                                         s[-1]["rss_mb"], s[-1]["n"], s[-1]["rss_kb_per_coord"],
                                                         (s[-1]["rss_mb"] - s[0]["rss_mb"]) * 1024 / (s[-1]["n"] - s[0]["n"])))
    if kind == "static":
        s = sorted((r for r in main if r["params"] == 0), key=lambda r: r["n"])
        if s:
            out.append("- tip deflection against Timoshenko's %.6e m (P and the weight, kappa = 5/6): %s" % (
                timoshenko_tip(), ", ".join("n = %d: %+.1e" % (r["n"], r["rel_diff"]) for r in s)))
    return out


def table(mr, kind):
    if kind == "run":
        md = ["| h [m] | Newton | par. | n | Newton it. | sens. solves | fact. (sens.) | fact. share | fill | wall [s] |"
              " us/step/coord | x plain | RSS [MB] | kB/coord | others [cores] | status |", "|---" * 16 + "|"]
    else:
        md = ["| h [m] | par. | n | load steps | Newton it. | fact. (sens.) | fact. share | fill | wall [s] | us/it./coord |"
              " x plain | RSS [MB] | kB/coord | tip deflection [m] | vs Timoshenko | others [cores] | status |",
              "|---" * 17 + "|"]
    for r in sorted(mr, key=sort_key):
        if not ok(r):
            cells = [fmt(r["size"], "%g")] + ([r["newton"]] if kind == "run" else []) + [str(r["params"])]
            md.append("| " + " | ".join(cells) + " | %s: `%s` |" % (r["status"], r["error"].replace("|", "/")))
            continue
        it = [fmt(r["iterations"], "%d"), fmt(r["sens_iterations"], "%d")] if kind == "run" else \
            [fmt(r["steps"], "%d"), fmt(r["iterations"], "%d")]
        work = ["%d (%d)" % (r["factorizations"], r["sens_factorizations"] or 0), fmt(r["fact_share"], "%.2f"),
                fmt(r["fill"], "%.2f"), fmt(r["wall_s"], "%.3g"), fmt(r["us_per_coord"], "%.2f"), fmt(r["overhead"], "%.2f"),
                fmt(r["rss_mb"], "%.0f"), fmt(r["rss_kb_per_coord"], "%.1f")]
        extra = [] if kind == "run" else ["%.6e" % r["tip_deflection_m"], "%+.1e" % r["rel_diff"]]
        cells = [fmt(r["size"], "%g")] + ([r["newton"]] if kind == "run" else []) + [str(r["params"]), fmt(r["n"], "%d")] + \
            it + work + extra + [fmt(r["others_cores"], "%.2f"), r["status"]]
        md.append("| " + " | ".join(cells) + " |")
    return md


def machine_line(rows):
    vals = sorted(r["others_cores"] for r in rows if r.get("others_cores") is not None and ok(r))
    if not vals:
        return "No completed rows."
    shared = vals[-1] > SHARED_CORES
    return ("**%s**: other processes used %.2f cores at most and %.2f in the median row (column `others`, from "
            "/proc/stat less the run's own CPU time); each row's times come from its one run, ratios compare rows, "
            "and the counters (iterations, factorizations, fill, n) do not depend on the machine."
            % ("Machine shared" if shared else "Machine quiet", vals[-1], vals[len(vals) // 2]))


def params_text(spec):
    p = spec["params"]
    return "1: %s; 10: %s" % (p[0][0], ", ".join("%s (%s.%s)" % (n, of, prop) for n, of, prop in p))


def profile_lines(profile, exe):
    if not profile:
        return []
    md = ["## Profile", "", "`perf record -F 499 -g` of the %s at h = %g m (n = %s), modified Newton, %d parameters (status %s, "
          "wall %s s, the whole process); `perf report --no-children --sort dso,symbol` (the library names the "
          "addresses it has no symbol for), top 5:" % (
              MODELS[profile["model"]]["title"], profile["size"], profile.get("n"), profile["params"], profile["status"],
              fmt(profile.get("wall_s"))), ""]
    if profile["funcs"]:
        md += ["| self % | function |", "|---|---|"] + ["| %.1f | `%s` |" % (pc, annotate(name, exe).replace("|", "/"))
                                                        for pc, name in profile["funcs"]]
        if profile.get("libraries"):
            md += ["", "By library (`--sort dso`): " + ", ".join("%s %.1f%%" % (name, pc) for pc, name in profile["libraries"])]
    else:
        md += ["(no profile: %s)" % profile.get("error", "perf wrote no samples")]
    return md + [""]


def write_md(outdir, rows, meta, done, exe):
    md = ["# Meshed bodies refined to n ~ 100k", ""]
    if not done:
        md += ["**Partial: written while the benchmark was still running.**", ""]
    runs = "; ".join("`%s` (flexsens %s, %s - %s UTC)" % (r["command"], r["commit"], r["started"], r["finished"] or "...")
                     for r in meta["runs"])
    md += ["Written by %s, on a %d-core machine. %s" % (runs, os.cpu_count(), machine_line(rows)), "",
           "Cost = `wall_time_s` of summary.json (the time integration or the static solve, without reading the scene "
           "and meshing) per step and coordinate (dynamics) or per Newton iteration and coordinate (statics: its one "
           "load step takes 2-3 iterations and, with parameters, one more factorization for the sensitivities); "
           "sens. solves = `sensitivity_iterations` (linear solves of the sensitivity systems with a factorization, "
           "refinement and GMRES steps included); fact. = factorizations, in brackets those the sensitivity solves took; fact. share = "
           "`factorization_seconds` / `wall_time_s`; fill = `lu_fill` (nnz of the factor over the matrix's); x plain = "
           "cost / cost of the same size and Newton variant without parameters; RSS = peak resident set of the "
           "process (meshing included); others = cores the rest of the machine used during the row.", "",
           "![cost per coordinate and RSS per coordinate against n](cost.png)", ""]
    for model, spec in MODELS.items():
        mr = [r for r in rows if r["model"] == model]
        if not mr:
            continue
        md += ["## %s" % spec["title"], "", "Setup: %s. Parameters: %s." % (spec["setup"], params_text(spec)), ""]
        md += table(mr, spec["kind"]) + [""] + summary_lines(mr, spec["kind"]) + [""]
    md += profile_lines(meta.get("profile"), exe)
    open(os.path.join(outdir, "results.md"), "w").write("\n".join(md) + "\n")


def plot(outdir, rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 5))
    colors = {"solid": "tab:purple", "panel": "tab:orange", "cantilever": "tab:green"}
    styles = {("modified", 0): "-o", ("modified", 10): "--s", ("full", 0): ":^", ("full", 10): "-.v"}
    for model, spec in MODELS.items():
        for (newton, p), style in styles.items():
            if spec["kind"] == "static" and newton != "full":
                continue
            s = sorted((r for r in rows if r["model"] == model and r["newton"] == newton and r["params"] == p and ok(r)),
                       key=lambda r: r["n"])
            if not s:
                continue
            label = "%s, %s, %d par." % (spec["title"], "static (per it.)" if spec["kind"] == "static" else newton + " Newton", p)
            ax1.loglog([r["n"] for r in s], [r["us_per_coord"] for r in s], style, color=colors[model], label=label)
            ax2.loglog([r["n"] for r in s], [r["rss_kb_per_coord"] for r in s], style, color=colors[model], label=label)
    ax1.set_ylabel("cost per step (static: per Newton iteration) and coordinate [us]")
    ax2.set_ylabel("peak RSS per coordinate [kB]")
    for ax in (ax1, ax2):
        ax.set_xlabel("coordinates n")
        ax.grid(True, which="both", alpha=0.3)
        if ax.lines:
            ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "cost.png"), dpi=110)
    plt.close(fig)

# ---------------------------------------------------------------------------------------------


def exported_neighbours(dso, address, exe):
    """'between A and B': the exported symbols (nm -D) of the library `dso` (as ldd finds it for
    exe) around an address perf has no symbol for (a static function of the library)."""
    ldd = subprocess.run(["ldd", exe], capture_output=True, text=True).stdout
    paths = [os.path.realpath(p) for p in re.findall(r"=> (\S+)", ldd)]
    path = next((p for p in paths if os.path.basename(p) == dso), None)
    if not path:
        return ""
    nm = subprocess.run(["nm", "-D", "--defined-only", path], capture_output=True, text=True).stdout
    syms = sorted((int(f[0], 16), f[2]) for f in (l.split() for l in nm.splitlines()) if len(f) == 3 and f[1] in "Tt")
    below = [s for s in syms if s[0] <= address]
    above = [s for s in syms if s[0] > address]
    return "between %s and %s" % (below[-1][1] if below else "the start", above[0][1] if above else "the end")


def annotate(name, exe):
    """'dso: 0x...' -> 'dso: 0x... (between A and B)'."""
    m = re.match(r"^(\S+): 0x([0-9a-f]+)$", name)
    if not m:
        return name
    where = exported_neighbours(m.group(1), int(m.group(2), 16), exe)
    return "%s (%s)" % (name, where) if where else name


def perf_top(data, sort, pattern, top):
    """The `top` largest self shares of `perf report --no-children --sort <sort>` (-g none: the
    same percentages without building the call graphs) as (percent, 'dso: symbol' or 'dso')."""
    rep = subprocess.run(["perf", "report", "-i", data, "--stdio", "--no-children", "--sort"] + sort + ["-g", "none"],
                         capture_output=True, text=True)
    found = []
    for line in rep.stdout.splitlines():
        m = re.match(pattern, line)
        if m:
            found.append((float(m.group(1)), ": ".join(m.groups()[1:])))
    return sorted(found, key=lambda f: -f[0])[:top]


def perf_profile(exe, rows, limit, wd):
    done = [r for r in rows if r["model"] == "solid" and r["newton"] == "modified" and r["params"] == 10 and ok(r)]
    if not done:
        return None
    size = min(r["size"] for r in done)
    data = os.path.join(wd, "solid.perf.data")
    r = run_case(exe, "solid", size, "modified", 10, limit, wd, perf_data=data)
    prof = dict(model="solid", size=size, params=10, status=r["status"], n=r.get("n"), wall_s=r.get("wall_s"), funcs=[],
                error=r["error"])
    if os.path.exists(data):
        prof["funcs"] = perf_top(data, ["dso,symbol"], r"^\s+(\d+(?:\.\d+)?)%\s+(\S+)\s+\[.\]\s+(\S.*?)(?:\s+-)*\s*$", 5)
        prof["libraries"] = perf_top(data, ["dso"], r"^\s+(\d+(?:\.\d+)?)%\s+(\S+)(?:\s+-)*\s*$", 4)
    return prof


def plan(args):
    """(model, size, newton, params) in running order: the full Newton runs only at sizes whose
    modified run (same model, 0 parameters, run before them) had n <= FULL_NEWTON_UP_TO."""
    for model in args.models:
        spec = MODELS[model]
        for size in sorted(spec["quick" if args.quick else "sizes"], reverse=True):
            if args.sizes and not any(abs(size / h - 1) < 1e-9 for h in args.sizes):
                continue
            for newton in (("modified", "full") if spec["kind"] == "run" else ("full",)):
                if spec["kind"] == "run" and newton not in args.newton:
                    continue
                for p in args.params:
                    yield model, size, newton, p


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--flexsens", default=os.path.join(ROOT, "build", "flexsens"))
    ap.add_argument("--quick", action="store_true", help="the two smallest sizes, into a temporary directory")
    ap.add_argument("--models", default=",".join(MODELS), help="of %s" % ", ".join(MODELS))
    ap.add_argument("--params", default="0,1,10", help="parameter counts (0, 1, 10)")
    ap.add_argument("--newton", default="modified,full", help="the dynamic models' Newton variants")
    ap.add_argument("--sizes", default="", help="only these element sizes [m] (of the models' lists)")
    ap.add_argument("--no-perf", action="store_true", help="no perf profile of the largest solid run")
    ap.add_argument("--time-limit", type=float, default=3600.0, help="per run [s]")
    ap.add_argument("--out", help="output directory (default bench/continuum; --quick: a new temporary one)")
    ap.add_argument("--report-only", action="store_true", help="no runs: results.md and cost.png again from results.csv")
    a = ap.parse_args()
    a.flexsens = os.path.abspath(a.flexsens)
    a.models = [m for m in a.models.split(",") if m]
    a.params = [int(p) for p in a.params.split(",") if p]
    a.newton = [n for n in a.newton.split(",") if n]
    a.sizes = [float(h) for h in a.sizes.split(",") if h]
    bad = [m for m in a.models if m not in MODELS] + [str(p) for p in a.params if p not in PARAM_COUNTS] + \
          [n for n in a.newton if n not in ("modified", "full")]
    if bad:
        sys.exit("continuum bench: unknown %s (models %s, parameters 0/1/10, Newton modified/full)"
                 % (", ".join(bad), ", ".join(MODELS)))
    if not os.access(a.flexsens, os.X_OK):
        sys.exit("continuum bench: no executable at %s (--flexsens)" % a.flexsens)
    a.out = a.out or (tempfile.mkdtemp(prefix="continuum_quick_") if a.quick else HERE)
    git = subprocess.run(["git", "-C", ROOT, "describe", "--always"], capture_output=True, text=True)
    # changed files besides this benchmark's own outputs make the binary's source uncertain
    changed = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no", "--", ".",
                              ":!bench/continuum/results.*", ":!bench/continuum/cost.png", ":!bench/continuum/meta.json"],
                             capture_output=True, text=True)
    a.commit = (git.stdout.strip() or "(no git)") + ("-dirty" if changed.stdout.strip() else "")
    return a


def run_all(args, rows, csv_path, meta):
    wd = tempfile.mkdtemp(prefix="continuum_runs_")
    small_n = {}  # (model, size) -> n of the modified run, for the full Newton cap
    for model, size, newton, p in plan(args):
        n = small_n.get((model, size)) or next((x["n"] for x in rows if (x["model"], x["size"]) == (model, size)
                                                 and ok(x)), None)
        if newton == "full" and MODELS[model]["kind"] == "run" and (n is None or n > FULL_NEWTON_UP_TO * 1.1):
            continue
        r = run_case(args.flexsens, model, size, newton, p, args.time_limit, wd)
        if ok(r) and newton == "modified":
            small_n[(model, size)] = r["n"]
        rows = [x for x in rows if (x["model"], x["size"], x["newton"], x["params"]) != (model, size, newton, p)] + [r]
        rows.sort(key=sort_key)
        derive(rows)
        print("%-10s h %-7g %-8s %2d par.: %-9s n %-6s wall %s s, RSS %.0f MB, others %.2f %s" % (
            model, size, newton, p, r["status"], r.get("n"), fmt(r.get("wall_s")), r["rss_mb"], r["others_cores"],
            r["error"][:120]), file=sys.stderr, flush=True)
        write_csv(csv_path, rows)
        write_md(args.out, rows, meta, done=False, exe=args.flexsens)
    if not args.no_perf and "solid" in args.models and 10 in args.params:
        asked = [r for r in rows if not args.sizes or r["size"] in args.sizes]  # the largest of the sizes asked for
        meta["profile"] = perf_profile(args.flexsens, asked, args.time_limit, wd) or meta.get("profile")
    shutil.rmtree(wd, ignore_errors=True)
    return rows


def main():
    args = parse_args()
    os.makedirs(args.out, exist_ok=True)
    csv_path, meta_path = os.path.join(args.out, "results.csv"), os.path.join(args.out, "meta.json")
    rows = read_csv(csv_path)  # the rows this run does not redo stay
    meta = json.load(open(meta_path)) if os.path.exists(meta_path) and rows else {"runs": []}
    if not args.report_only:
        started = time.strftime("%Y-%m-%d %H:%M", time.gmtime())
        meta["runs"].append(dict(command=" ".join(["bench/continuum/run.py"] + sys.argv[1:]), commit=args.commit,
                                 started=started, finished=None))
        rows = run_all(args, rows, csv_path, meta)
        meta["runs"][-1]["finished"] = time.strftime("%Y-%m-%d %H:%M", time.gmtime())
        json.dump(meta, open(meta_path, "w"), indent=1)
    derive(rows)
    write_csv(csv_path, rows)
    write_md(args.out, rows, meta, done=True, exe=args.flexsens)
    plot(args.out, rows)
    print("continuum bench: %s/results.md, results.csv, cost.png" % args.out)


if __name__ == "__main__":
    main()
