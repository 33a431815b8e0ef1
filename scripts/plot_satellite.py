#!/usr/bin/env python3
"""Figure 12 of the PIM paper for the satellite, beside the run flexsens trusts.

    python3 scripts/plot_satellite.py RESULTS_DIR

Left: dx_B2/dL_B1B2 of SAT1 and SAT2 with BDF-1 at the paper's dt = 0.02 s
(RESULTS_DIR/satellite/SAT*), the run as published: BDF-1 dissipates most of the energy, so
the audit calls it suspect and its converging curves are that damping. Middle: the same
sensitivity from the run flexsens trusts, the massless-spring model with the trapezoidal rule
and projections, dt = 1 ms, over 3 s (RESULTS_DIR/satellite_trusted/SAT*; complete). Right:
panel 1's opening angle from both.
"""
import csv
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

PAPER = ("satellite", "BDF-1, dt = 0.02 s (paper; suspect: numerical damping)")
TRUSTED = ("satellite_trusted", "trapezoidal + projections, massless springs, dt = 1 ms (trusted)")


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def series(root, run):
    paths = {c: os.path.join(root, run, c, "series.csv") for c in ("SAT1", "SAT2")}
    missing = [p for p in paths.values() if not os.path.exists(p)]
    if missing:
        sys.exit("plot_satellite: missing %s (run scripts/run-main.sh first)" % ", ".join(missing))
    return {c: read(p) for c, p in paths.items()}


def sensitivity_panel(ax, runs, color, title):
    for case, style in (("SAT1", "-"), ("SAT2", "--")):
        d = runs[case]
        ax.plot(d["t"], d["dxB2/dL_B1B2"], style, color=color, label=case)
    ax.set_title(title, fontsize=10)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("dx_B2 / dL_B1B2  [m/m]")
    ax.legend()
    ax.grid(True, alpha=0.3)


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "results"
    paper, trusted = series(root, PAPER[0]), series(root, TRUSTED[0])
    fig, (a, g, b) = plt.subplots(1, 3, figsize=(17, 4.5))
    sensitivity_panel(a, paper, "C0", PAPER[1])
    sensitivity_panel(g, trusted, "C2", TRUSTED[1])
    for runs, color, label in ((paper, "C0", PAPER[1]), (trusted, "C2", TRUSTED[1])):
        d = runs["SAT1"]
        b.plot(d["t"], [math.degrees(x) for x in d["open1"]], color=color, label=label)
    b.set_xlabel("t [s]")
    b.set_ylabel("opening angle of panel 1 [deg]")
    b.set_title("Panel 1 opening (nominal motion)", fontsize=10)
    b.axhline(90, color="k", lw=0.5)
    b.legend(fontsize=8)
    b.grid(True, alpha=0.3)
    fig.tight_layout()
    out = os.path.join(root, "plots")
    os.makedirs(out, exist_ok=True)
    fig.savefig(os.path.join(out, "fig12_satellite.png"), dpi=85)
    print("plot_satellite: %s" % os.path.join(out, "fig12_satellite.png"))


if __name__ == "__main__":
    main()
