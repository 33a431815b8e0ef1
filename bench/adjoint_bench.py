#!/usr/bin/env python3
"""Cost and agreement of `flexsens gradient` by the discrete adjoint and by the forward
sensitivities (not a test). Writes bench/adjoint/results.md, cost.csv and cost.png.

1. Agreement: adjoint against forward gradient, worst relative difference over objectives and
   parameters, on the flexible five-bar (trapezoidal, plain model: L_A1, L_B1), the massless
   satellite (BDF-1, case SAT1, 0.2 s) with an angle output, the ANCF pendulum
   (generalized-alpha), the shell panel (midpoint rule, 0.05 s).
2. Cost against the number of parameters: a planar cantilever plate of linear triangles under
   gravity (tests/scenes/solid/plate.geo), 100 steps of the trapezoidal rule, at three mesh
   sizes (about 100, 800 and 1000 cells); on each mesh a plain run (`flexsens run`, no
   parameters) and gradients for 1 (E), 3 (E, nu, density) and one thickness per cell
   (per: element) parameters. Wall times from summary.json / gradient.json (scene reading,
   meshing and output excluded); peak RSS of the whole process (/usr/bin/time); cost.png.
3. Memory with checkpointing: the five-bar at k = N (every state kept), k = 71 and k = 8.
4. IDAS' continuous adjoint (integrator idas, rtol 1e-8): against IDAS' forward sensitivities
   on the ANCF pendulum (E, density; 1 s), with IDAS' checkpoints every 5000 (default) and
   every 50 steps, and for a terminal objective; and its cost on the plate with one thickness per cell (size 0.025, 0.1 s),
   where the forward sensitivities are not run (531 s measured once, 2026-11-28).

    python3 bench/adjoint_bench.py [--flexsens build/flexsens]
"""
import argparse, csv, json, os, re, shutil, subprocess, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "bench", "adjoint")


def with_objectives(src, objectives, wd, name, replace=None):
    """The scene at src with its objectives (if any) replaced by `objectives`, written into wd
    beside copies of the files it names."""
    text = open(src).read()
    text = re.sub(r"\nobjectives:\n(  .*\n|  #.*\n)*", "\n", text)
    for a, b in (replace or []):
        text = text.replace(a, b)
    for f in os.listdir(os.path.dirname(src)):
        if f.endswith((".geo", ".msh", ".csv")):
            shutil.copy(os.path.join(os.path.dirname(src), f), wd)
    path = os.path.join(wd, name)
    open(path, "w").write(text.rstrip("\n") + "\n" + objectives)
    return path


def gradient(exe, scene, method, wd, extra=()):
    out = os.path.join(wd, "g_%s_%s" % (os.path.basename(scene), method))
    cmd = ["/usr/bin/time", "-f", "%M", exe, "gradient", scene, "--method", method, "--out", out] + list(extra)
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode not in (0, 5):
        raise SystemExit("failed: %s\n%s" % (" ".join(cmd), p.stderr))
    rss_kb = int(p.stderr.strip().splitlines()[-1])
    return json.load(open(os.path.join(out, "gradient.json"))), rss_kb


def worst(a, f):
    w = 0.0
    for x, y in zip(a, f):
        scale = max(abs(v) for v in y["gradient"].values()) or 1.0
        for k, v in y["gradient"].items():
            w = max(w, abs(x["gradient"][k] - v) / max(abs(v), 1e-6 * scale))
    return w


def agreement(exe, wd):
    cases = [
        ("flexible five-bar, trapezoidal", "examples/fivebar/flexible.yaml", [],
         "  - {name: z2_end, terminal: {output: z2}}\n  - {name: z2_sq, integral: {output: z2, power: 2, from: 1, to: 4}}\n"
         "  - {name: z2_peak, max: {output: z2, rho: 20}}\n", []),
        ("massless satellite SAT1, bdf1, 0.2 s", "examples/satellite/satellite_massless.yaml", ["--case", "SAT1", "--t-end", "0.2"],
         "  - {name: xB2_end, terminal: {output: xB2}}\n  - {name: open_sq, integral: {output: open1, power: 2}}\n", []),
        ("ANCF pendulum, generalized_alpha", "examples/ancf/pendulum.yaml", ["--integrator", "generalized_alpha", "--t-end", "0.5"],
         "  - {name: y_end, terminal: {output: y_tip}}\n  - {name: x_track, tracking: {output: x_tip, target: {type: harmonic, amplitude: 1, omega: 3}}}\n",
         [("integrator:\n", "parameters:\n  - {name: E, of: rod, property: E}\n  - {name: rho, of: rod, property: density}\nintegrator:\n")]),
        ("shell panel F1, midpoint, 0.05 s", "examples/shell/panel.yaml", ["--case", "F1", "--integrator", "midpoint", "--t-end", "0.05"],
         "  - {name: tip_end, terminal: {output: tip_z}}\n  - {name: tip_peak, max: {output: tip_z, rho: 100}}\n", []),
    ]
    rows = []
    for label, src, extra, objectives, replace in cases:
        scene = with_objectives(os.path.join(ROOT, src), "objectives:\n" + objectives, wd, os.path.basename(src), replace)
        a, rss_a = gradient(exe, scene, "adjoint", wd, extra)
        f, rss_f = gradient(exe, scene, "forward", wd, extra)
        sa, sf = a[0]["statistics"], f[0]["statistics"]
        rows.append((label, len(a[0]["gradient"]), sa["steps"], worst(a, f), sa["wall_time_s"], sf["wall_time_s"], sa["status"]))
        print(rows[-1], flush=True)
    return rows


PLATE = """dimension: 2
gravity: [0, -9.81]
elements:
  - {name: plate, type: solid, mesh: plate.geo, group: plate, size: %g, E: 2.0e6, nu: 0.3, density: 1000, thickness: 0.01, ground: [root]}
%s
integrator: {type: trapezoidal, t_end: 0.1, dt: 0.001, newton: full}
outputs:
  - {name: tip_y, node: tipmid, component: y}
objectives:
  - {name: tip_end, terminal: {output: tip_y}}
output: {vtk: false}
"""
# Parameter sets on one mesh: whole-plate E; E, nu, density; one thickness per cell. (The
# plate's thickness alone would not move the tip: mass and stiffness both scale with it.)
PARAMETER_SETS = (["{name: E, of: plate, property: E}"],
                  ["{name: E, of: plate, property: E}", "{name: nu, of: plate, property: nu}",
                   "{name: rho, of: plate, property: density}"],
                  ["{name: t, of: plate, property: thickness, per: element}"])
COST_SIZES = (0.045, 0.0125, 0.011)  # about 100, 800 and 1000 cells


def plain_run(exe, scene, wd):
    """`flexsens run` of the scene without parameters and objectives: wall_time_s, peak RSS [kB]."""
    out = os.path.join(wd, "plain_" + os.path.basename(scene))
    p = subprocess.run(["/usr/bin/time", "-f", "%M", exe, "run", scene, "--out", out], capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit("failed: plain run of %s\n%s" % (scene, p.stderr))
    return json.load(open(os.path.join(out, "summary.json")))["wall_time_s"], int(p.stderr.strip().splitlines()[-1])


def cost(exe, wd):
    """Rows (size, Np, plain [s], plain RSS [kB], adjoint [s], forward [s], adjoint RSS, forward RSS,
    adjoint vs forward): whole runs' wall_time_s (integration and gradient; scene reading,
    meshing and output excluded) and peak RSS of the whole process."""
    shutil.copy(os.path.join(ROOT, "tests", "scenes", "solid", "plate.geo"), wd)
    rows = []
    for size in COST_SIZES:
        plain_scene = os.path.join(wd, "plate_%g_plain.yaml" % size)
        open(plain_scene, "w").write((PLATE % (size, "")).replace("objectives:\n  - {name: tip_end, terminal: {output: tip_y}}\n", ""))
        plain_s, plain_rss = plain_run(exe, plain_scene, wd)
        for i, params in enumerate(PARAMETER_SETS):
            path = os.path.join(wd, "plate_%g_%d.yaml" % (size, i))
            open(path, "w").write(PLATE % (size, "parameters:\n" + "".join("  - %s\n" % q for q in params)))
            a, rss_a = gradient(exe, path, "adjoint", wd)
            f, rss_f = gradient(exe, path, "forward", wd)
            rows.append((size, len(a[0]["gradient"]), plain_s, plain_rss, a[0]["statistics"]["wall_time_s"],
                         f[0]["statistics"]["wall_time_s"], rss_a, rss_f, worst(a, f)))
            print(rows[-1], flush=True)
    return rows


def plot_cost(rows, png):
    """Cost / plain run against Np per mesh, adjoint and forward, with the crossover."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4))
    for size in COST_SIZES:
        r = sorted((x for x in rows if x[0] == size), key=lambda x: x[1])
        n = [x[1] for x in r]
        ax.plot(n, [x[4] / x[2] for x in r], "o-", label="adjoint, h = %g m (%d cells)" % (size, n[-1]))
        ax.plot(n, [x[5] / x[2] for x in r], "s--", label="forward, h = %g m" % size)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("parameters Np")
    ax.set_ylabel("gradient cost / plain run")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def crossover(rows, size):
    """Np where the forward cost, a line through the smallest and the largest set, meets the
    adjoint's (its mean over the sets)."""
    r = sorted((x for x in rows if x[0] == size), key=lambda x: x[1])
    (n0, f0), (n1, f1) = (r[0][1], r[0][5]), (r[-1][1], r[-1][5])
    slope = (f1 - f0) / (n1 - n0)
    adjoint = sum(x[4] for x in r) / len(r)
    return max(1.0, n0 + (adjoint - f0) / slope) if slope > 0 else float("nan")


def memory(exe, wd):
    scene = with_objectives(os.path.join(ROOT, "examples/fivebar/flexible.yaml"),
                            "objectives:\n  - {name: z2_end, terminal: {output: z2}}\n", wd, "fivebar_mem.yaml")
    rows, ref = [], None
    for k in (None, 71, 8):
        a, rss = gradient(exe, scene, "adjoint", wd, ["--checkpoint-every", str(k)] if k else [])
        s = a[0]["statistics"]
        g = a[0]["gradient"]
        ref = ref or g
        diff = max(abs(g[p] - ref[p]) / abs(ref[p]) for p in g)
        rows.append((s["checkpoint_every"], s["checkpoints"], s["peak_states"], s["peak_state_bytes"], s["recomputed_steps"],
                     s["wall_time_s"], diff))
        print(rows[-1], flush=True)
    return rows


ANCF_IDAS = [("integrator:\n", "parameters:\n  - {name: E, of: rod, property: E}\n  - {name: rho, of: rod, property: density}\nintegrator:\n")]


def idas(exe, wd):
    """Rows: scene, parameters, forward-pass steps, checkpoints, backward steps, worst difference
    to the forward sensitivities (None: not run), forward pass [s], adjoint [s], forward [s]."""
    scene = with_objectives(os.path.join(ROOT, "examples/ancf/pendulum.yaml"),
                            "objectives:\n  - {name: y_sq, integral: {output: y_tip, power: 2}}\n", wd, "ancf_idas.yaml", ANCF_IDAS)
    rows = []
    f, _ = gradient(exe, scene, "forward", wd, ["--integrator", "idas"])
    for k in (None, 50):
        a, _ = gradient(exe, scene, "adjoint", wd, ["--integrator", "idas"] + (["--checkpoint-every", str(k)] if k else []))
        s = a[0]["statistics"]
        rows.append(("ANCF pendulum, 1 s, checkpoint every %d" % s["checkpoint_every"], len(a[0]["gradient"]), s["steps"],
                     s["checkpoints"], s["backward_steps"], worst(a, f), s["forward_pass_s"], s["wall_time_s"],
                     f[0]["statistics"]["wall_time_s"]))
        print(rows[-1], flush=True)
    terminal = with_objectives(os.path.join(ROOT, "examples/ancf/pendulum.yaml"),
                               "objectives:\n  - {name: y_end, terminal: {output: y_tip}}\n", wd, "ancf_idas_end.yaml", ANCF_IDAS)
    f, _ = gradient(exe, terminal, "forward", wd, ["--integrator", "idas"])
    a, _ = gradient(exe, terminal, "adjoint", wd, ["--integrator", "idas"])
    s = a[0]["statistics"]
    rows.append(("ANCF pendulum, 1 s, terminal y_tip at t_end", len(a[0]["gradient"]), s["steps"], s["checkpoints"],
                 s["backward_steps"], worst(a, f), s["forward_pass_s"], s["wall_time_s"], f[0]["statistics"]["wall_time_s"]))
    print(rows[-1], flush=True)
    path = os.path.join(wd, "plate_idas.yaml")
    open(path, "w").write((PLATE % (0.025, "parameters:\n  - {name: t, of: plate, property: thickness, per: element}"))
                          .replace("{type: trapezoidal, t_end: 0.1, dt: 0.001, newton: full}", "{type: idas, t_end: 0.1, dt: 0.001}")
                          .replace("{name: tip_end, terminal: {output: tip_y}}", "{name: tip_sq, integral: {output: tip_y, power: 2}}"))
    a, _ = gradient(exe, path, "adjoint", wd)
    s = a[0]["statistics"]
    rows.append(("plate 0.025, 0.1 s, one thickness per cell", len(a[0]["gradient"]), s["steps"], s["checkpoints"],
                 s["backward_steps"], None, s["forward_pass_s"], s["wall_time_s"], None))
    print(rows[-1], flush=True)
    return rows


def idas_markdown(rows):
    md = ["", "## IDAS: the continuous adjoint (integrator idas, rtol 1e-8)", "",
          "The continuous-time adjoint (IDASolveB/IDAQuadB, checkpoints, Hermite interpolation) differentiates the",
          "exact solution: it agrees with IDAS' forward sensitivities to the integration tolerance, not to round-off.",
          "forward pass: the adjoint's IDAS run without sensitivities (with checkpoints and the objective's quadrature).", "",
          "| scene | parameters | IDAS steps | checkpoints | backward steps | adjoint vs forward | forward pass [s] | adjoint [s] | forward [s] | adjoint / forward pass |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    for label, n, st, ck, bs, d, fp, a, f in rows:
        md.append("| %s | %d | %d | %d | %d | %s | %.3f | %.3f | %s | %.1f |" % (
            label, n, st, ck, bs, "%.1e" % d if d is not None else "not run", fp, a, "%.3f" % f if f is not None else "531 (once)", a / fp))
    return md


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexsens", default=os.path.join(ROOT, "build", "flexsens"))
    args = ap.parse_args()
    exe = os.path.abspath(args.flexsens)
    os.makedirs(OUT, exist_ok=True)
    with tempfile.TemporaryDirectory() as wd:
        agree, costs, mem, idas_rows = agreement(exe, wd), cost(exe, wd), memory(exe, wd), idas(exe, wd)
    with open(os.path.join(OUT, "cost.csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["size_m", "parameters", "plain_s", "plain_rss_kB", "adjoint_s", "forward_s", "adjoint_rss_kB",
                    "forward_rss_kB", "adjoint_vs_forward"])
        w.writerows(costs)
    md = ["# Discrete adjoint: agreement, cost, memory", "",
          "Written by `python3 bench/adjoint_bench.py` (2 cores shared with other work: wall times are indicative;",
          "gradient.json holds 12 significant digits, so differences below ~1e-12 read as 0).", "",
          "## Adjoint against forward gradient", "",
          "| scene | parameters | steps | worst relative difference | adjoint [s] | forward [s] | status |", "|---|---|---|---|---|---|---|"]
    md += ["| %s | %d | %d | %.2e | %.3f | %.3f | %s |" % r for r in agree]
    plot_cost(costs, os.path.join(OUT, "cost.png"))
    md += ["", "## Cost against the number of parameters (plate, 100 steps)", "",
           "Each mesh: a plain run (`flexsens run`, no parameters), then `flexsens gradient` with one parameter (E),",
           "three (E, nu, density) and one thickness per cell. Times: wall_time_s of summary.json / gradient.json",
           "(integration and gradient; scene reading, meshing and output excluded). RSS: peak of the whole process.",
           "![cost](cost.png)", "",
           "| element size [m] | parameters | plain run [s] | adjoint [s] | forward [s] | adjoint / plain | forward / plain | RSS plain [MB] | RSS adjoint [MB] | RSS forward [MB] | RSS adjoint / plain | adjoint vs forward |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    md += ["| %g | %d | %.3f | %.3f | %.3f | %.2f | %.1f | %.0f | %.0f | %.0f | %.2f | %.1e |" %
           (s, n, p, a, f, a / p, f / p, rp / 1024, ra / 1024, rf / 1024, ra / rp, d) for s, n, p, rp, a, f, ra, rf, d in costs]
    md += ["", "Crossover (the forward cost as a line through the smallest and the largest Np, meeting the adjoint's mean cost): " +
           ", ".join("h = %g m: Np = %.1f" % (z, crossover(costs, z)) for z in COST_SIZES)]
    md += ["", "## Memory with checkpointing (flexible five-bar, 5000 steps)", "",
           "| k | checkpoints | states held at once | their memory [kB] | recomputed steps | wall [s] | gradient change |",
           "|---|---|---|---|---|---|---|"]
    md += ["| %d | %d | %d | %.1f | %d | %.3f | %.1e |" % (k, c, p, b / 1024, r, w, d) for k, c, p, b, r, w, d in mem]
    md += idas_markdown(idas_rows)
    open(os.path.join(OUT, "results.md"), "w").write("\n".join(md) + "\n")
    print("\n".join(md))


if __name__ == "__main__":
    main()
