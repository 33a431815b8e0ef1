#!/usr/bin/env python3
"""The main job's scenes, each run to its end whatever its status, and the status table.

    python3 scripts/main_job.py [--quick] [--exe build/flexsens] [--results results]

Every run of the table below is made; each case's summary.json gives its status and reason.
A row is expected when its status is the one the table names and, for `suspect`, its reason
contains the expected words (a suspect for another reason is not the expected one). The job
exits 1 when any row is unexpected: a crash or numerical failure, a missing summary, a status
or reason the table does not expect, or a plot that could not be made.
"""
import argparse
import json
import os
import subprocess
import sys
import time
from dataclasses import dataclass, field


@dataclass
class Expect:
    status: str          # complete | suspect
    reason: str = ""     # words the suspect's reason must contain


@dataclass
class Job:
    scene: str                       # relative to the checkout
    out: str                         # relative to the results folder
    integrator: str                  # as the table prints it
    shows: str                       # what the row demonstrates, one line
    full: dict                       # case ('' for none) -> Expect, full job
    quick: dict = None               # the same for --quick (default: as full)
    args: list = field(default_factory=list)
    quick_args: list = field(default_factory=list)  # --quick: these flags replace args' own


def expect_all(cases, status, reason=""):
    return {c: Expect(status, reason) for c in cases}


FIVEBAR_F = ["F1", "F1R", "F2", "F2R", "F3", "F3R", "F4", "F4R", "F5", "F5R", "F6", "F6R"]
BLOWUP = "sensitivity blow-up"
DISSIPATED = "dissipated"

JOBS = [
    Job("examples/fivebar/rigid.yaml", "fivebar_rigid", "trapezoidal",
        "paper fig. 4 over 2 s: the motion amplifies perturbations, so dz2/dL_A1 passes 1e3 of "
        "the size at t = 1.5 s in every integrator (trapezoidal, generalized-alpha, IDAS agree); "
        "trust the sensitivities to 1.5 s",
        expect_all(["R1", "R2", "R3"], "suspect", BLOWUP),
        expect_all(["R1", "R2", "R3"], "complete"), quick_args=["--t-end", "1"]),
    Job("examples/fivebar/flexible.yaml", "fivebar_flexible", "trapezoidal",
        "paper figs. 7 and 9: PIM cases F1-F6 and their rigid twins F-R, sensitivities of z2",
        expect_all(FIVEBAR_F, "complete"), quick_args=["--t-end", "0.5"]),
    Job("examples/seed000/double_pendulum.yaml", "double_pendulum", "trapezoidal",
        "3D rigid bodies in natural coordinates, a revolute chain",
        {"": Expect("complete")}, quick_args=["--t-end", "1"]),
    Job("examples/seed000/four_bar.yaml", "four_bar", "trapezoidal",
        "a closed loop of 3D rigid bodies",
        {"": Expect("complete")}, quick_args=["--t-end", "1"]),
    Job("examples/satellite/satellite.yaml", "satellite", "bdf1, dt 0.02 s",
        "paper fig. 12 as published: BDF-1 at the paper's step dissipates ~95% of the energy "
        "scale (the paper says so: 'significant numerical damping'); its converging SAT1/SAT2 "
        "curves are that damping; the trusted comparison is the next row",
        expect_all(["SAT1", "SAT2"], "suspect", DISSIPATED),
        quick_args=["--t-end", "4"]),
    Job("examples/satellite/satellite_massless.yaml", "satellite_trusted",
        "trapezoidal + projections, dt 1 ms",
        "the run flexsens trusts for fig. 12: massless springs (no spurious spring vibrations), "
        "no numerical damping, energy kept to 0.5% over 3 s; the sensitivities pass the blow-up "
        "limit at ~3.4 s, where the motion itself stops converging in dt",
        expect_all(["SAT1", "SAT2"], "complete"),
        args=["--integrator", "trapezoidal", "--projections", "on", "--dt", "0.001", "--t-end", "3"],
        quick_args=["--t-end", "1"]),
]


def options(base, override):
    """base's `--flag value` pairs with override's replacing those of the same flag."""
    pairs = dict(zip(base[::2], base[1::2]))
    pairs.update(zip(override[::2], override[1::2]))
    return [x for kv in pairs.items() for x in kv]


def run_job(job, exe, results, quick):
    out = os.path.join(results, job.out)
    cmd = [exe, "run", job.scene, "--out", out] + options(job.args, job.quick_args if quick else [])
    start = time.time()
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wall = time.time() - start
    expected = (job.quick if (quick and job.quick is not None) else job.full)
    rows = []
    for case, exp in expected.items():
        summary = os.path.join(out, case, "summary.json") if case else os.path.join(out, "summary.json")
        rows.append(judge(job, case, exp, summary, proc.returncode, proc.stderr))
    return rows, wall, " ".join(cmd)


def judge(job, case, exp, summary, rc, stderr):
    row = {"scene": job.scene.replace("examples/", ""), "case": case or "-",
           "integrator": job.integrator, "shows": job.shows}
    if rc not in (0, 5):
        last = stderr.strip().splitlines()[-1] if stderr.strip() else "no message"
        return dict(row, status=f"exit {rc}", reason=last, ok=False)
    try:
        with open(summary) as f:
            s = json.load(f)
    except (OSError, ValueError) as e:
        return dict(row, status="no summary", reason=str(e), ok=False)
    status, reason = s.get("status", "?"), (s.get("error") or "").strip()
    ok = status == exp.status and (exp.status != "suspect" or exp.reason in reason)
    if not ok and status == exp.status:
        reason = f"expected a suspect for '{exp.reason}', got: {reason}"
    elif not ok:
        reason = f"expected '{exp.status}'" + (f": {reason}" if reason else "")
    return dict(row, status=status, reason=first_clause(reason) if ok else reason, ok=ok)


def first_clause(reason):
    """The reason's first clause (up to ';'), for one table line."""
    return reason.split(";")[0].strip() if reason else ""


def run_plots(results):
    rows = []
    for script in ("scripts/plot_fivebar.py", "scripts/plot_satellite.py"):
        p = subprocess.run([sys.executable, script, results], stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True)
        rows.append((script, p.returncode, p.stdout.strip().splitlines()[-1:] or [""]))
    return rows


def run_render(results, quick):
    """ParaView frames of SAT2's deployment (every 5th frame; every 10th in --quick)."""
    run = os.path.join(results, "satellite", "SAT2")
    steps = [["bash", "scripts/install-paraview.sh"],
             ["bash", "scripts/render-frames.sh", run, os.path.join(run, "png"), "L_B1B2",
              "--every", "10" if quick else "5"]]
    for cmd in steps:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if p.returncode != 0:
            return [(" ".join(cmd), p.returncode, p.stdout.strip().splitlines()[-1:] or [""])]
    return []


def print_table(rows):
    heads = ("scene", "case", "integrator", "status", "as expected", "reason")
    cells = [(r["scene"], r["case"], r["integrator"], r["status"], "yes" if r["ok"] else "NO",
              r["reason"][:110]) for r in rows]
    widths = [max(len(h), *(len(c[i]) for c in cells)) for i, h in enumerate(heads)]
    line = lambda c: "  ".join(str(x).ljust(w) for x, w in zip(c, widths)).rstrip()
    print(line(heads))
    print(line(["-" * w for w in widths]))
    for c in cells:
        print(line(c))


def print_shows(jobs):
    print("\nWhat each scene shows:")
    for j in jobs:
        print(f"  {j.scene.replace('examples/', '')} ({j.integrator}): {j.shows}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="shorter runs, same scenes and table")
    ap.add_argument("--exe", default="build/flexsens")
    ap.add_argument("--results", default="results")
    a = ap.parse_args()
    rows = []
    for job in JOBS:
        r, wall, cmd = run_job(job, a.exe, a.results, a.quick)
        print(f"main job: {cmd}  ({wall:.1f} s)", flush=True)
        rows += r
    plots = run_plots(a.results) + run_render(a.results, a.quick)
    print()
    print_table(rows)
    print_shows(JOBS)
    bad_plots = [p for p in plots if p[1] != 0]
    for script, rc, last in bad_plots:
        print(f"\npicture failed: {script} (exit {rc}): {last[0]}")
    unexpected = sum(not r["ok"] for r in rows)
    print(f"\nmain job: {len(rows)} runs, {len(rows) - unexpected} as expected, {unexpected} unexpected"
          + (f", {len(bad_plots)} picture step(s) failed" if bad_plots else ""))
    return 1 if unexpected or bad_plots else 0


if __name__ == "__main__":
    sys.exit(main())
