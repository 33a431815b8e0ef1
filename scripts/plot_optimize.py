#!/usr/bin/env python3
"""history.png for the folder written by `flexsens optimize` (reads optimize.json, history.csv
and, with more than 20 variables, history_variables.csv).

Top: the objective against the evaluation (log scale when it stays positive and spans more
than two decades), the best evaluation circled. Middle (with constraints): each constraint's
objective with its bound dashed. Bottom: the variables (up to 20, each scaled to its bounds:
0 the lower, 1 the upper), or with more of them their minimum, mean and maximum over the
variables, scaled the same way. A failed evaluation is a red cross.
   python3 scripts/plot_optimize.py <optimize folder>
"""
import csv
import json
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def num(x):
    try:
        v = float(x)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


def load(d):
    with open(os.path.join(d, "optimize.json")) as f:
        meta = json.load(f)
    with open(os.path.join(d, "history.csv")) as f:
        rows = list(csv.DictReader(f))
    wide = os.path.join(d, "history_variables.csv")
    variables = None
    if os.path.exists(wide):
        with open(wide) as f:
            variables = list(csv.DictReader(f))
    bounds = {}
    with open(os.path.join(d, "optimum.csv")) as f:
        for r in csv.DictReader(f):
            bounds[r["parameter"]] = (float(r["lower"]), float(r["upper"]))
    return meta, rows, variables, bounds


def plot_objective(ax, meta, rows):
    ev = [int(r["evaluation"]) for r in rows if num(r["objective"]) is not None]
    J = [num(r["objective"]) for r in rows if num(r["objective"]) is not None]
    ax.plot(ev, J, "o-", ms=3, label=meta["objective"])
    if J and min(J) > 0 and max(J) / min(J) > 100:
        ax.set_yscale("log")
    best = meta.get("optimum")
    if best:
        ax.plot([best["evaluation"]], [best["objective"]], "o", mfc="none", mec="k", ms=10, label="best")
    for r in rows:
        if r["status"] == "failed":
            ax.axvline(int(r["evaluation"]), color="r", ls=":")
            ax.plot([int(r["evaluation"])], [J[-1] if J else 0], "rx", ms=10, label="failed evaluation")
    ax.set_ylabel("objective")
    ax.set_title("flexsens optimize: %s, %s (%s), %d evaluations, status %s"
                 % (meta["objective"], meta["algorithm"], meta["nlopt_result"], meta["evaluations"], meta["status"]),
                 fontsize=9)
    ax.legend(fontsize=8)


def plot_constraints(ax, meta, rows):
    for c in meta["constraints"]:
        name = c["objective"]
        ev = [int(r["evaluation"]) for r in rows if num(r.get(name)) is not None]
        ax.plot(ev, [num(r[name]) for r in rows if num(r.get(name)) is not None], "o-", ms=3, label=name)
        bound = c.get("max", c.get("min"))
        ax.axhline(bound, ls="--", color="k", lw=0.8)
    ax.set_ylabel("constraints (bounds dashed)")
    ax.legend(fontsize=8)


def scaled(value, bound):
    lo, hi = bound
    return (value - lo) / (hi - lo)


def plot_variables(ax, rows, variables, bounds):
    names = list(bounds)
    source = variables if variables is not None else rows
    ev = [int(r["evaluation"]) for r in source]
    if len(names) <= 20:
        for n in names:
            ax.plot(ev, [scaled(float(r[n]), bounds[n]) for r in source], "o-", ms=2, label=n)
        if len(names) <= 8:
            ax.legend(fontsize=8)
    else:
        s = [[scaled(float(r[n]), bounds[n]) for n in names] for r in source]
        ax.fill_between(ev, [min(v) for v in s], [max(v) for v in s], alpha=0.3, label="min ... max")
        ax.plot(ev, [sum(v) / len(v) for v in s], "o-", ms=2, label="mean of %d variables" % len(names))
        ax.legend(fontsize=8)
    ax.set_ylabel("variables (0 lower, 1 upper)")
    ax.set_xlabel("evaluation")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    d = sys.argv[1]
    meta, rows, variables, bounds = load(d)
    panels = 3 if meta["constraints"] else 2
    fig, axes = plt.subplots(panels, 1, figsize=(7, 2.6 * panels), sharex=True)
    plot_objective(axes[0], meta, rows)
    if meta["constraints"]:
        plot_constraints(axes[1], meta, rows)
    plot_variables(axes[-1], rows, variables, bounds)
    for ax in axes:
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(d, "history.png"), dpi=110)


if __name__ == "__main__":
    main()
