#!/usr/bin/env python3
"""Flexible-pendulum work-precision in one run (not a test): positions-only beam vs ANCF cable
(and, in 3D, the fully parameterized ANCF beam, 3243).

The pendulum of issue 15: L = 1 m, square side 0.02 m, density 7850 kg/m^3, E = 2e8 Pa, pinned
at the origin, released horizontal under gravity, 1 s. Planar (default) or, with --3d, spatial
with an out-of-plane initial velocity (the rod turning about the vertical axis through the pin
at --omega rad/s: node velocity omega x r; the ANCF slopes' and gradients' rates follow from that
rigid motion). The 3243 beam (`ancf_beam`, 3D only) needs nu (0.3 here: it only sets its shear
modulus, its normal stresses are uncoupled) and carries shear and the section's rotary inertia,
which the cable and the positions-only beam do not: its limit is not exactly the cable's, so
the bench measures that difference (IDAS, N = 32) and reports it beside its errors.

Error = max over t = 0.25, 0.5, 0.75, 1 s of |tip - reference| [m]. The reference is an IDAS run
(ANCF cable, N = 32, rtol 1e-10); the bench also reports how far it is from IDAS at rtol 1e-9
(time) and from the positions-only beam's Richardson extrapolation (space), so its own error is
stated, not assumed.
--sens: the rod's E is a scene parameter and every run computes its sensitivities (discrete
direct, `--method dd`, flexsens' default); the error is max over the four times of
|dy_tip/dE - reference| (3D: dz_tip/dE) [m/Pa], the reference the same IDAS run with
sensitivities, checked against IDAS at rtol 1e-9 and against central differences of two IDAS
runs (rtol 1e-10) at E (1 +- --fd-step). Targets: --sens-target (1e-4, 1e-3, 1e-2) times max |reference|.
CPU = user + system CPU of the flexsens process (resource.getrusage of the child: robust to a
busy machine, unlike wall time; the least of --repeats runs), with and without the process'
fixed start-up (linking VTK, Gmsh, reading the scene) measured by the cheapest of three one-step
runs of the same model.

Work-precision: every (element, N, dt) run with the same integrator (--integrator, default the
trapezoidal rule; a comma list runs each on the same references, one table each;
generalized_alpha uses --rho-inf, default 0.9); for each element the cheapest measured run whose
error is <= --target (1e-5 m); the ratio of the two CPU times is the acceptance number of
issue 15 (ANCF <= 1/3).

    python3 bench/ancf_pendulum_bench.py [--flexsens build/flexsens] [--3d] [--sens]
        [--integrator trapezoidal,generalized_alpha]
Writes bench/ancf_pendulum/<tag>.csv and <tag>.md, tag = wp_2d_trapezoidal, wp_3d_generalized_alpha_sens etc.
"""
import argparse, csv, hashlib, json, math, os, resource, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "bench", "ancf_pendulum")
TIMES = [0.25, 0.5, 0.75, 1.0]
E0 = 2.0e8  # Young's modulus of the rod [Pa]
NU = 0.3    # ancf_beam only: sets G = E / (2 (1 + nu)); bending gives EI exactly (uncoupled normal stresses)
NAME = {"beam": "beam", "ancf_cable": "ANCF cable", "ancf_beam": "ANCF beam 3243"}


def scene(kind, n, integ, dim, omega, t_end=1.0, E=E0, sens=False):
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
    mat = "E: %.17g, " % E + ("nu: %g, " % NU if kind == "ancf_beam" else "")
    return ("dimension: %d\ngravity: %s\nnodes:\n" % (dim, grav) + "".join(lines) +
            "elements:\n  - {name: rod, type: %s, nodes: [%s], %sdensity: 7850, section: {side: 0.02}}\n"
            % (kind, chain, mat) +
            ("parameters:\n  - {name: E, of: rod, property: E}\n" if sens else "") +
            "integrator: {%s, t_end: %.17g, frame_interval: 0.25, energy_tolerance: 0}\n" % (integ, t_end) +
            "outputs:\n" + "".join("  - {name: %s_tip, node: n%d, component: %s}\n" % (c, n, c)
                                   for c in (["x", up] if dim == 2 else ["x", "y", "z"])) +
            "output: {vtk: false, plots: false}\n")


def cpu_of_children():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(exe, text, wd, tag):
    """The series.csv rows at TIMES ({t: {column: value}}) and the process' CPU [s]."""
    path = os.path.join(wd, tag + ".yaml")
    open(path, "w").write(text)
    out = os.path.join(wd, tag)
    c0 = cpu_of_children()
    r = subprocess.run([exe, "run", path, "--out", out], capture_output=True, text=True)
    cpu = cpu_of_children() - c0
    if r.returncode != 0:
        print("  failed:", tag, r.stderr.strip().splitlines()[-1:] if r.stderr else "", flush=True)
        return None, cpu
    rows = {}
    for row in csv.DictReader(open(os.path.join(out, "series.csv"))):
        t = float(row["t"])
        for T in TIMES:
            if abs(t - T) < 1e-9:
                rows[T] = {k: float(v) for k, v in row.items()}
    return rows, cpu


def tip(row):
    return [v for k, v in row.items() if k.endswith("_tip")]


def distance(a, b, times=TIMES):
    return max(math.sqrt(sum((x - y) ** 2 for x, y in zip(tip(a[T]), tip(b[T])))) for T in times)


def sens_distance(a, b, key):
    return max(abs(a[T][key] - b[T][key]) for T in TIMES)


def integ_text(kind, dt, rho_inf):
    if kind == "generalized_alpha":
        return "type: generalized_alpha, rho_inf: %g, dt: %g" % (rho_inf, dt)
    return "type: %s, dt: %g" % (kind, dt)


def idas(rtol):
    return "type: idas, rtol: %g, atol: %g" % (rtol, rtol * 1e-2)


def grids(three, sens, quick):
    """{element: [(N, [dt, ...]), ...]} of one sweep."""
    if quick:
        g = {"beam": [16], "ancf_cable": [4]}
        if three:
            g["ancf_beam"] = [4]
        return {k: [(n, [1e-3]) for n in ns] for k, ns in g.items()}
    if not three:
        if sens:
            # The sensitivity's time error is larger than the tip's (see bench.md): finer steps.
            dts = [5e-4, 2.5e-4, 1.25e-4, 6.25e-5, 3.125e-5]
            g = {"beam": [64, 128, 192], "ancf_cable": [12, 16, 24, 32]}
        else:
            dts = [1e-3, 5e-4, 2.5e-4, 1.25e-4]
            g = {"beam": [32, 64, 128, 192, 256], "ancf_cable": [4, 8, 12, 16, 20, 24, 32]}
        return {k: [(n, dts) for n in ns] for k, ns in g.items()}
    # 3D: fewer runs, each costs ~1.5x the planar one; the 3243 beam (24 coordinates and 12
    # Gauss points per element) ~7x the cable per element, and its limit differs from the
    # cable's by ~1e-4 m (shear, rotary inertia), so its finest steps would only measure that.
    if sens:
        dts = [2.5e-4, 1.25e-4, 6.25e-5, 3.125e-5]
        return {"beam": [(n, dts) for n in [64, 128]], "ancf_cable": [(n, dts) for n in [16, 24, 32]],
                "ancf_beam": [(n, [2.5e-4, 1.25e-4]) for n in [16, 32]]}
    dts = [5e-4, 2.5e-4, 1.25e-4]
    g = {"beam": [(n, dts) for n in [64, 128, 192, 256]], "ancf_cable": [(n, dts) for n in [8, 16, 24, 32]],
         "ancf_beam": [(n, [5e-4, 2.5e-4]) for n in [16, 32, 64]]}
    return g


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexsens", default=os.path.join(ROOT, "build", "flexsens"))
    ap.add_argument("--3d", dest="three", action="store_true")
    ap.add_argument("--omega", type=float, default=2.0, help="3D: initial turn rate about the vertical [rad/s]")
    ap.add_argument("--integrator", default="trapezoidal", help="one or a comma list (one table each)")
    ap.add_argument("--rho-inf", type=float, default=0.9, help="generalized_alpha's spectral radius at infinity")
    ap.add_argument("--target", type=float, default=1e-5, help="tip error target [m]")
    ap.add_argument("--mode", default="plain", choices=["plain", "sens", "both"],
                    help="tip work-precision, that of dy_tip/dE (3D: dz_tip/dE), or both on one set of references")
    ap.add_argument("--sens-target", default="1e-4,1e-3,1e-2",
                    help="sens: targets (a comma list) as fractions of max |reference|")
    ap.add_argument("--retarget", default=None, metavar="TAG",
                    help="only rewrite the cheapest-run sections of the sensitivity table TAG for --sens-target")
    ap.add_argument("--fd-step", type=float, default=1e-4, help="sens: relative step of the central differences")
    ap.add_argument("--beam3243-rtol", type=float, default=1e-8,
                    help="3D: rtol of the 3243 beam's IDAS run (N = 32) that measures its limit against the cable's")
    ap.add_argument("--ref-cache", default=None,
                    help="JSON file keeping the IDAS reference runs by scene text: a later run of the same scenes "
                         "(e.g. --mode sens after --mode both) reads them instead of recomputing (delete it after "
                         "changing the model code)")
    ap.add_argument("--quick", action="store_true", help="a few runs, loose references (smoke test of the script)")
    ap.add_argument("--repeats", type=int, default=3, help="runs per point; the least CPU counts (busy machine)")
    ap.add_argument("--sens-repeats", type=int, default=None, help="runs per point of the sensitivity sweeps")
    a = ap.parse_args()
    a.sens_target = [float(x) for x in a.sens_target.split(",")]
    if a.retarget:
        return retarget(a.retarget, a.sens_target)
    dim = 3 if a.three else 2
    up = "y" if dim == 2 else "z"
    key = "d%s_tip/dE" % up
    integrators = a.integrator.split(",")
    sens = a.mode != "plain"
    rtol_ref = 1e-6 if a.quick else 1e-10
    with tempfile.TemporaryDirectory() as wd:
        refs = {}

        cache = json.load(open(a.ref_cache)) if a.ref_cache and os.path.exists(a.ref_cache) else {}

        def reference(name, kind, n, rtol, E=E0, with_sens=sens):
            text = scene(kind, n, idas(rtol), dim, a.omega, E=E, sens=with_sens)
            h = hashlib.sha1(text.encode()).hexdigest()
            cached = h in cache
            if cached:
                rows, cpu = {float(t): r for t, r in cache[h]["rows"].items()}, cache[h]["cpu"]
            else:
                rows, cpu = run(a.flexsens, text, wd, name)
                if rows is None:
                    sys.exit("reference run %s failed" % name)
                if a.ref_cache:
                    cache[h] = {"name": name, "rows": rows, "cpu": cpu}
                    json.dump(cache, open(a.ref_cache, "w"))
            refs[name] = (rows, cpu)
            print(name, "cpu %.1f s%s" % (cpu, " (from --ref-cache)" if cached else ""), flush=True)

        # The reference (with sensitivities when any table needs them: the same positions, and
        # the sensitivities' error control can only make them more accurate).
        reference("ref", "ancf_cable", 32, rtol_ref)
        # Its checks. Time: rtol 1e-9 (1e-11 exceeds IDAS' step limit).
        reference("ref_time", "ancf_cable", 32, rtol_ref * 10)
        if sens:
            # The sensitivity against central differences of whole runs (no sensitivities in them).
            reference("E_plus", "ancf_cable", 32, rtol_ref, E0 * (1 + a.fd_step), False)
            reference("E_minus", "ancf_cable", 32, rtol_ref, E0 * (1 - a.fd_step), False)
        if a.mode != "sens":
            # Space: the positions-only beam's Richardson extrapolation (4 b(128) - b(64)) / 3
            # (an independent discretization); the 3243 beam's own limit at N = 32.
            reference("beam64", "beam", 64, rtol_ref, with_sens=False)
            reference("beam128", "beam", 128, rtol_ref, with_sens=False)
            if a.three:
                reference("beam3243_32", "ancf_beam", 32, 1e-6 if a.quick else a.beam3243_rtol, with_sens=False)
        ref = refs["ref"][0]
        scale = max(abs(ref[T][key]) for T in TIMES) if sens else None
        for s in ([False] if a.mode == "plain" else [True] if a.mode == "sens" else [False, True]):
            g = grids(a.three, s, a.quick)
            repeats = a.sens_repeats if s and a.sens_repeats else a.repeats
            # Start-up CPU: the same model, one step (the first integrator; start-up does not depend on it).
            overhead = {}
            for kind, runs in g.items():
                for n, _ in runs:
                    overhead[(kind, n)] = min(
                        run(a.flexsens, scene(kind, n, integ_text(integrators[0], 1e-3, a.rho_inf), dim, a.omega,
                                              1e-3, sens=s), wd, "one_%s_%d_%d" % (kind, n, k))[1] for k in range(3))
            for integ in integrators:
                res, kept = [], {}
                for kind, runs in g.items():
                    for n, dts in runs:
                        for dt in dts:
                            cpu = float("inf")
                            for k in range(repeats):
                                rows, c = run(a.flexsens, scene(kind, n, integ_text(integ, dt, a.rho_inf), dim,
                                                                a.omega, sens=s),
                                              wd, "%s_%s_%d_%g_%d" % (integ, kind, n, dt, k))
                                cpu = min(cpu, c)
                            kept[(kind, n, dt)] = rows
                            err = distance(rows, ref) if rows else float("nan")
                            if s:
                                serr = sens_distance(rows, ref, key) if rows else float("nan")
                                res.append((kind, n, dt, serr, serr / scale, err, cpu, cpu - overhead[(kind, n)]))
                                print("%s %-10s N=%3d dt=%-7g d%s/dE err %.3e (rel %.2e) tip err %.2e cpu %.3f s "
                                      "(%.3f s after start-up)" % ((integ, kind, n, dt, up) + res[-1][3:]), flush=True)
                            else:
                                res.append((kind, n, dt, err, cpu, cpu - overhead[(kind, n)]))
                                print("%s %-10s N=%3d dt=%-7g err %.3e cpu %.3f s (%.3f s after start-up)"
                                      % ((integ,) + res[-1]), flush=True)
                write(a, dim, up, key, integ, s, list(g), refs, scale, res, repeats, kept)


def write(a, dim, up, key, integ, sens, kinds, refs, scale, res, repeats, rows):
    tag = "wp_%dd_%s%s" % (dim, integ, "_sens" if sens else "")
    ref = refs["ref"][0]
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, tag + ".csv"), "w") as f:
        if sens:
            f.write("element,N,dt,d%s_tip_dE_error_m_per_Pa,relative_error,tip_error_m,cpu_s,cpu_after_startup_s\n" % up)
            for row in res:
                f.write("%s,%d,%g,%.6e,%.6e,%.6e,%.4f,%.4f\n" % row)
        else:
            f.write("element,N,dt,tip_error_m,cpu_s,cpu_after_startup_s\n")
            for row in res:
                f.write("%s,%d,%g,%.6e,%.4f,%.4f\n" % row)
    ecol, targets = (4, a.sens_target) if sens else (3, [a.target])
    integ_name = integ + (" (rho_inf %g)" % a.rho_inf if integ == "generalized_alpha" else "")
    with open(os.path.join(OUT, tag + ".md"), "w") as f:
        f.write("# Flexible pendulum work-precision%s, %dD, %s (bench/ancf_pendulum_bench.py%s%s)\n\n"
                % (", d%s_tip/dE" % up if sens else "", dim, integ_name, " --3d" if a.three else "",
                   " --mode %s" % a.mode if a.mode != "plain" else ""))
        if a.three:
            f.write("Initial velocity: the rod turning at %g rad/s about the vertical through the pin "
                    "(out of the swing plane).\n" % a.omega)
        if sens:
            f.write("Reference: IDAS with sensitivities (dd), ANCF cable N = 32, rtol 1e-10 (CPU %.1f s); "
                    "max over t of |d%s_tip/dE| = %.4e m/Pa (E d%s/dE = %.4e m). Error = max over t = 0.25, 0.5, "
                    "0.75, 1 s of |d%s_tip/dE - reference|; relative error = error / max |reference|.\n"
                    % (refs["ref"][1], up, scale, up, scale * E0, up))
            if "ref_time" in refs:
                cd = {T: {key: (refs["E_plus"][0][T]["%s_tip" % up] - refs["E_minus"][0][T]["%s_tip" % up])
                          / (2 * a.fd_step * E0)} for T in TIMES}
                f.write("Reference checks: IDAS at rtol 1e-9 differs by %.2e relative (time); central differences "
                        "of two IDAS runs (rtol 1e-10, no sensitivities) at E (1 +- %g) by %.2e relative.\n"
                        % (sens_distance(refs["ref_time"][0], ref, key) / scale, a.fd_step,
                           sens_distance(cd, ref, key) / scale))
        else:
            f.write("Reference: IDAS, ANCF N = 32, rtol 1e-10%s (CPU %.1f s). Error = max over t = 0.25, 0.5, 0.75, 1 s "
                    "of |tip - reference|.\n" % (" (the run with the sensitivities to E of --mode both)"
                                                  if a.mode == "both" else "", refs["ref"][1]))
            if "ref_time" in refs:
                b64, b128 = refs["beam64"][0], refs["beam128"][0]
                rich = {T: {k: (4 * b128[T][k] - b64[T][k]) / 3 for k in b64[T]} for T in TIMES}
                f.write("Reference checks: IDAS N = 32 at rtol 1e-9 differs by %.2e m (time); the positions-only "
                        "beam's Richardson extrapolation (4 b(128) - b(64)) / 3 of IDAS runs (rtol 1e-10) by %.2e m "
                        "(space; b(128) alone: %.2e m).\n"
                        % (distance(refs["ref_time"][0], ref), distance(rich, ref), distance(b128, ref)))
            if "beam3243_32" in refs:
                f.write("The 3243 beam's own limit: its IDAS run at N = 32 (rtol %g, CPU %.1f s) differs from the "
                        "reference by %.2e m (per time: %s m).\n"
                        % (a.beam3243_rtol, refs["beam3243_32"][1], distance(refs["beam3243_32"][0], ref),
                           ", ".join("%.1e" % distance(refs["beam3243_32"][0], ref, [T])
                                     for T in TIMES)))
        if "ancf_beam" in kinds:
            # The 3243 beam against itself: successive N at the smallest dt it ran.
            dtb = min(r[2] for r in res if r[0] == "ancf_beam")
            ns = sorted(r[1] for r in res if r[0] == "ancf_beam" and r[2] == dtb)
            rb = {n: rows[("ancf_beam", n, dtb)] for n in ns}
            if all(rb[n] for n in ns):
                d = [(sens_distance(rb[m], rb[n], key) / scale if sens else distance(rb[m], rb[n]))
                     for m, n in zip(ns, ns[1:])]
                f.write("The 3243 beam against itself at dt = %g (%s): %s.\n"
                        % (dtb, "relative d%s/dE" % up if sens else "tip [m]",
                           ", ".join("N = %d vs %d: %.2e" % (m, n, x) for (m, n), x in zip(zip(ns, ns[1:]), d))))
        f.write("CPU = user + system CPU of the process%s, least of %d runs; 'after start-up' subtracts the "
                "cheapest of three one-step runs of the same model (linking, reading, building: "
                "~0.25 s).\n\n" % (" with sensitivities" if sens else "", repeats))
        if sens:
            f.write("| element | N | dt [s] | d%s/dE error [m/Pa] | relative | tip error [m] | CPU [s] | "
                    "CPU after start-up [s] |\n|---|---|---|---|---|---|---|---|\n" % up)
            for row in res:
                f.write("| %s | %d | %g | %.3e | %.2e | %.2e | %.3f | %.3f |\n" % row)
        else:
            f.write("| element | N | dt [s] | tip error [m] | CPU [s] | CPU after start-up [s] |\n"
                    "|---|---|---|---|---|---|\n")
            for row in res:
                f.write("| %s | %d | %g | %.3e | %.3f | %.3f |\n" % row)
        for target in targets:
            cheapest_section(f, res, kinds, ecol, target, "relative d%s/dE error" % up if sens else "tip error")


def cheapest_section(f, res, kinds, ecol, target, what_err):
    cpucol = len(res[0]) - 2

    def cheapest(kind, col, converged):
        # converged: the error stays <= target also at every smaller dt of the same N (no
        # lucky cancellation of the space and time errors at one point of the sweep).
        ok = [r for r in res if r[0] == kind and r[ecol] <= target and
              (not converged or all(x[ecol] <= target for x in res if x[0] == kind and x[1] == r[1] and x[2] < r[2]))]
        return min(ok, key=lambda r: r[col]) if ok else None

    f.write("\n## Cheapest run with %s <= %g%s\n\n" % (what_err, target, " m" if what_err == "tip error" else ""))
    f.write("'converged': also every smaller dt of the same N stays <= %g.\n\n" % target)
    for col, conv, what in [(cpucol, False, "CPU"), (cpucol + 1, False, "CPU after start-up"),
                            (cpucol, True, "CPU, converged"), (cpucol + 1, True, "CPU after start-up, converged")]:
        best = {k: cheapest(k, col, conv) for k in kinds}
        parts = ["%s N = %d, dt = %g: %.3f s" % (NAME[k], best[k][1], best[k][2], best[k][col]) if best[k]
                 else "%s: none" % NAME[k] for k in kinds]
        ratios = ["%s / beam = %.3f" % (NAME[k], best[k][col] / best["beam"][col])
                  for k in kinds if k != "beam" and best[k] and best["beam"]]
        f.write("- %s: %s%s\n" % (what, "; ".join(parts), ("; " + "; ".join(ratios)) if ratios else ""))


def retarget(tag, targets):
    """Rewrite the 'Cheapest run' sections of a sensitivity table's md from its csv for other targets."""
    res = []
    for r in csv.DictReader(open(os.path.join(OUT, tag + ".csv"))):
        v = list(r.values())
        res.append((v[0], int(v[1])) + tuple(float(x) for x in v[2:]))
    kinds = list(dict.fromkeys(r[0] for r in res))
    md = os.path.join(OUT, tag + ".md")
    text = open(md).read()
    up = "z" if "_3d_" in tag else "y"
    with open(md, "w") as f:
        f.write(text[:text.index("\n## Cheapest")] + "\n")
        for target in targets:
            cheapest_section(f, res, kinds, 4, target, "relative d%s/dE error" % up)

if __name__ == "__main__":
    main()
