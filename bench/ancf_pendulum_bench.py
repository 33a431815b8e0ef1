#!/usr/bin/env python3
"""Flexible-pendulum work-precision in one run (not a test): positions-only beam vs ANCF cable.

The pendulum of issue 15: L = 1 m, square side 0.02 m, density 7850 kg/m^3, E = 2e8 Pa, pinned
at the origin, released horizontal under gravity, 1 s. Planar (default) or, with --3d, spatial
with an out-of-plane initial velocity (the rod turning about the vertical axis through the pin
at --omega rad/s: node velocity omega x r; the ANCF slopes' rates follow from that rigid motion).

Error = max over t = 0.25, 0.5, 0.75, 1 s of |tip - reference| [m]. The reference is an IDAS run
(ANCF cable, N = 32, rtol 1e-10); the bench also reports how far it is from IDAS at rtol 1e-9
(time) and from the positions-only beam's Richardson extrapolation (space), so its own error is
stated, not assumed.
CPU = user + system CPU of the flexsens process (resource.getrusage of the child: robust to a
busy machine, unlike wall time; the least of --repeats runs), with and without the process'
fixed start-up (linking VTK, Gmsh, reading the scene) measured by the cheapest of three one-step
runs of the same model.

Work-precision: every (element, N, dt) run with the same integrator (--integrator, default the
trapezoidal rule); for each element the cheapest measured run whose error is <= --target
(1e-5 m); the ratio of the two CPU times is the acceptance number of issue 15 (ANCF <= 1/3).

    python3 bench/ancf_pendulum_bench.py [--flexsens build/flexsens] [--3d] [--integrator T]
Writes bench/ancf_pendulum/<tag>.csv and <tag>.md, tag = wp_2d_trapezoidal etc.
"""
import argparse, csv, math, os, resource, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "bench", "ancf_pendulum")
TIMES = [0.25, 0.5, 0.75, 1.0]


def scene(kind, n, integ, dim, omega, t_end=1.0):
    lines = []
    for i in range(n + 1):
        x = i / n
        if dim == 2:
            pos = "[%.17g, 0]" % x
            extra = ""
        else:
            pos = "[%.17g, 0, 0]" % x
            extra = ", velocity: [0, %.17g, 0]" % (omega * x) if i > 0 and omega else ""
        lines.append("  - {name: n%d, position: %s%s%s}\n" % (i, pos, ", ground: true" if i == 0 else "", extra))
    chain = ", ".join("n%d" % i for i in range(n + 1))
    grav = "[0, -9.81]" if dim == 2 else "[0, 0, -9.81]"
    up = "y" if dim == 2 else "z"
    return ("dimension: %d\ngravity: %s\nnodes:\n" % (dim, grav) + "".join(lines) +
            "elements:\n  - {name: rod, type: %s, nodes: [%s], E: 2.0e8, density: 7850, section: {side: 0.02}}\n"
            % (kind, chain) +
            "integrator: {%s, t_end: %.17g, frame_interval: 0.25, energy_tolerance: 0}\n" % (integ, t_end) +
            "outputs:\n" + "".join("  - {name: %s_tip, node: n%d, component: %s}\n" % (c, n, c)
                                   for c in (["x", up] if dim == 2 else ["x", "y", "z"])) +
            "output: {vtk: false, plots: false}\n")


def cpu_of_children():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(exe, text, wd, tag):
    path = os.path.join(wd, tag + ".yaml")
    open(path, "w").write(text)
    out = os.path.join(wd, tag)
    c0 = cpu_of_children()
    r = subprocess.run([exe, "run", path, "--out", out], capture_output=True, text=True)
    cpu = cpu_of_children() - c0
    if r.returncode != 0:
        print("  failed:", tag, r.stderr.strip().splitlines()[-1:] if r.stderr else "", flush=True)
        return None, cpu
    rows = list(csv.DictReader(open(os.path.join(out, "series.csv"))))
    tips = {}
    for row in rows:
        t = float(row["t"])
        for T in TIMES:
            if abs(t - T) < 1e-9:
                tips[T] = [float(v) for k, v in row.items() if k.endswith("_tip")]
    return tips, cpu


def distance(a, b):
    return max(math.sqrt(sum((x - y) ** 2 for x, y in zip(a[T], b[T]))) for T in TIMES)


def integ_text(kind, dt):
    if kind == "generalized_alpha":
        return "type: generalized_alpha, rho_inf: 0.9, dt: %g" % dt
    return "type: %s, dt: %g" % (kind, dt)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexsens", default=os.path.join(ROOT, "build", "flexsens"))
    ap.add_argument("--3d", dest="three", action="store_true")
    ap.add_argument("--omega", type=float, default=2.0, help="3D: initial turn rate about the vertical [rad/s]")
    ap.add_argument("--integrator", default="trapezoidal")
    ap.add_argument("--target", type=float, default=1e-5)
    ap.add_argument("--quick", action="store_true", help="a few runs only (smoke test of the script)")
    ap.add_argument("--repeats", type=int, default=3, help="runs per point; the least CPU counts (busy machine)")
    a = ap.parse_args()
    dim = 3 if a.three else 2
    tag = "wp_%dd_%s" % (dim, a.integrator)
    Ns = {"beam": [32, 64, 128, 192, 256], "ancf_cable": [4, 8, 12, 16, 20, 24, 32]}
    dts = [1e-3, 5e-4, 2.5e-4, 1.25e-4]
    if a.three:  # fewer runs: each costs ~1.5x the planar one
        Ns = {"beam": [64, 128, 192, 256], "ancf_cable": [8, 16, 24, 32]}
        dts = [5e-4, 2.5e-4, 1.25e-4]
    if a.quick:
        Ns = {"beam": [16], "ancf_cable": [4]}
        dts = [1e-3]
    with tempfile.TemporaryDirectory() as wd:
        refs = {}
        # The reference and its checks: time (rtol 1e-9; 1e-11 exceeds IDAS' step limit) and space, against the positions-only
        # beam's Richardson extrapolation (4 b(128) - b(64)) / 3 (an independent discretization).
        for name, kind, n, rtol in [("ref", "ancf_cable", 32, 1e-10), ("ref_time", "ancf_cable", 32, 1e-9),
                                    ("beam64", "beam", 64, 1e-10), ("beam128", "beam", 128, 1e-10)]:
            if a.quick and name != "ref":
                continue
            integ = "type: idas, rtol: %g, atol: %g" % (rtol, rtol * 1e-2)
            tips, cpu = run(a.flexsens, scene(kind, n, integ, dim, a.omega), wd, name)
            if tips is None:
                sys.exit("reference run %s failed" % name)
            refs[name] = (tips, cpu)
            print(name, "cpu %.1f s" % cpu, flush=True)
        ref = refs["ref"][0]
        # Start-up CPU: the same model, one step.
        overhead = {}
        for kind, ns in Ns.items():
            for n in ns:
                overhead[(kind, n)] = min(
                    run(a.flexsens, scene(kind, n, integ_text(a.integrator, 1e-3), dim, a.omega, 1e-3), wd,
                        "one_%s_%d_%d" % (kind, n, k))[1] for k in range(3))
        res = []
        for kind, ns in Ns.items():
            for n in ns:
                for dt in dts:
                    cpu = float("inf")
                    for k in range(a.repeats):
                        tips, c = run(a.flexsens, scene(kind, n, integ_text(a.integrator, dt), dim, a.omega), wd,
                                      "%s_%d_%g_%d" % (kind, n, dt, k))
                        cpu = min(cpu, c)
                    err = distance(tips, ref) if tips else float("nan")
                    res.append((kind, n, dt, err, cpu, cpu - overhead[(kind, n)]))
                    print("%-10s N=%3d dt=%-7g err %.3e cpu %.3f s (%.3f s after start-up)" % res[-1], flush=True)
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, tag + ".csv"), "w") as f:
        f.write("element,N,dt,tip_error_m,cpu_s,cpu_after_startup_s\n")
        for row in res:
            f.write("%s,%d,%g,%.6e,%.4f,%.4f\n" % row)

    def cheapest(kind, col, converged):
        # converged: the error stays <= target also at every smaller dt of the same N (no
        # lucky cancellation of the space and time errors at one point of the sweep).
        ok = [r for r in res if r[0] == kind and r[3] <= a.target and
              (not converged or all(x[3] <= a.target for x in res if x[0] == kind and x[1] == r[1] and x[2] < r[2]))]
        return min(ok, key=lambda r: r[col]) if ok else None

    with open(os.path.join(OUT, tag + ".md"), "w") as f:
        f.write("# Flexible pendulum work-precision, %dD, %s (bench/ancf_pendulum_bench.py%s)\n\n"
                % (dim, a.integrator, " --3d" if a.three else ""))
        if a.three:
            f.write("Initial velocity: the rod turning at %g rad/s about the vertical through the pin "
                    "(out of the swing plane).\n" % a.omega)
        f.write("Reference: IDAS, ANCF N = 32, rtol 1e-10 (CPU %.1f s). Error = max over t = 0.25, 0.5, 0.75, 1 s "
                "of |tip - reference|.\n" % refs["ref"][1])
        if "ref_time" in refs:
            b64, b128 = refs["beam64"][0], refs["beam128"][0]
            rich = {T: [(4 * y - x) / 3 for x, y in zip(b64[T], b128[T])] for T in TIMES}
            f.write("Reference checks: IDAS N = 32 at rtol 1e-9 differs by %.2e m (time); the positions-only "
                    "beam's Richardson extrapolation (4 b(128) - b(64)) / 3 of IDAS runs (rtol 1e-10) by %.2e m "
                    "(space; b(128) alone: %.2e m).\n"
                    % (distance(refs["ref_time"][0], ref), distance(rich, ref), distance(b128, ref)))
        f.write("CPU = user + system CPU of the process, least of %d runs; 'after start-up' subtracts the "
                "cheapest of three one-step runs of the same model (linking, reading, building: "
                "~0.25 s).\n\n" % a.repeats)
        f.write("| element | N | dt [s] | tip error [m] | CPU [s] | CPU after start-up [s] |\n|---|---|---|---|---|---|\n")
        for row in res:
            f.write("| %s | %d | %g | %.3e | %.3f | %.3f |\n" % row)
        f.write("\n## Cheapest run with tip error <= %g m\n\n"
                "'converged': also every smaller dt of the same N stays <= %g m.\n\n" % (a.target, a.target))
        for col, conv, what in [(4, False, "CPU"), (5, False, "CPU after start-up"),
                                (4, True, "CPU, converged"), (5, True, "CPU after start-up, converged")]:
            b, c = cheapest("beam", col, conv), cheapest("ancf_cable", col, conv)
            if b and c:
                f.write("- %s: beam N = %d, dt = %g: %.3f s; ANCF N = %d, dt = %g: %.3f s; ANCF / beam = %.3f\n"
                        % (what, b[1], b[2], b[col], c[1], c[2], c[col], c[col] / b[col]))
            else:
                f.write("- %s: %s reaches %g m in no run of this sweep\n"
                        % (what, "beam" if not b else "ANCF", a.target))


if __name__ == "__main__":
    main()
