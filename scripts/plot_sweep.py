#!/usr/bin/env python3
"""sweep.png for the table written by `flexsens sweep` (reads sweep.json and sweep.csv).

One swept parameter: each output against it, one curve per PIM case, with the sensitivity
d(output)/d(parameter) drawn as a short tangent at every sample (where the table holds it).
Two: the response surface of each output (filled contours; a grid or the scattered samples).
More: a scatter matrix, each output against each parameter. Samples that did not complete
(failed, lost, interrupted) are red crosses on the parameter axes.
   python3 scripts/plot_sweep.py <sweep folder>
"""
import csv
import json
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

GOOD = ("complete", "suspect")
MAX_PANELS = 12


def num(x):
    try:
        v = float(x)
        return v if math.isfinite(v) else None
    except ValueError:
        return None


def load(d):
    with open(os.path.join(d, "sweep.json")) as f:
        meta = json.load(f)
    with open(os.path.join(d, "sweep.csv")) as f:
        rows = list(csv.DictReader(f))
    return meta, rows


def responses(meta):
    """The value columns (not sensitivities), in table order."""
    return [c for c in meta["columns"] if c["parameter"] is None][:MAX_PANELS]


def sensitivity(meta, column, parameter):
    for c in meta["columns"]:
        if c["output"] == column["output"] and c["parameter"] == parameter and c.get("time") == column.get("time"):
            return c["header"]
    return None


def by_case(meta, rows):
    cases = meta["cases"] if meta["cases"] != [""] else [""]
    return [(c, [r for r in rows if r.get("case", "") == c]) for c in cases]


def mark_failures(ax, rows, px, py=None):
    bad = [r for r in rows if r["status"] not in GOOD]
    if not bad:
        return
    y0 = ax.get_ylim()[0]
    xs = [float(r[px]) for r in bad]
    ys = [float(r[py]) for r in bad] if py else [y0] * len(bad)
    ax.plot(xs, ys, "x", color="red", ms=8, mew=2, label=f"not complete ({len(bad)})", zorder=5)


def curves(meta, rows, p):
    cols = responses(meta)
    fig, axes = plt.subplots(len(cols), 1, figsize=(8, 3.4 * len(cols)), squeeze=False)
    xs_all = sorted({float(r[p]) for r in rows})
    span = (xs_all[-1] - xs_all[0]) / max(len(xs_all) - 1, 1)
    for ax, col in zip(axes.flat, cols):
        dcol = sensitivity(meta, col, p)
        for j, (case, crows) in enumerate(by_case(meta, rows)):
            good = sorted((float(r[p]), num(r[col["header"]]), num(r[dcol]) if dcol else None)
                          for r in crows if r["status"] in GOOD and num(r[col["header"]]) is not None)
            if not good:
                continue
            ax.plot([g[0] for g in good], [g[1] for g in good], "o-", color=f"C{j}", label=case or None)
            for x, y, s in good:  # the tangent the sensitivity predicts, over +-0.3 sample spacings
                if s is not None:
                    h = 0.3 * span
                    ax.plot([x - h, x + h], [y - s * h, y + s * h], "-", color=f"C{j}", lw=2.5, alpha=0.45)
        mark_failures(ax, rows, p)
        ax.set_xlabel(p)
        ax.set_ylabel(col["header"])
        ax.grid(True, alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8)
    fig.suptitle("sweep: outputs over " + p + (" (tangents: the sensitivities)" if meta["columns"] else ""))
    return fig


def surfaces(meta, rows, p, q):
    cases = by_case(meta, rows)
    panels = [(col, case, crows) for col in responses(meta) for case, crows in cases][:MAX_PANELS]
    ncol = min(2, len(panels))
    nrow = (len(panels) + ncol - 1) // ncol
    fig, axes = plt.subplots(nrow, ncol, figsize=(6.5 * ncol, 5 * nrow), squeeze=False)
    for ax, (col, case, crows) in zip(axes.flat, panels):
        good = [(float(r[p]), float(r[q]), num(r[col["header"]])) for r in crows if r["status"] in GOOD]
        good = [g for g in good if g[2] is not None]
        if len(good) >= 3 and len({g[0] for g in good}) > 1 and len({g[1] for g in good}) > 1:
            cs = ax.tricontourf([g[0] for g in good], [g[1] for g in good], [g[2] for g in good], levels=14)
            fig.colorbar(cs, ax=ax, label=col["header"])
        ax.plot([g[0] for g in good], [g[1] for g in good], "k.", ms=4)
        mark_failures(ax, crows, p, q)
        ax.set_xlabel(p)
        ax.set_ylabel(q)
        ax.set_title(col["header"] + (f", case {case}" if case else ""), fontsize=10)
    for ax in list(axes.flat)[len(panels):]:
        ax.set_visible(False)
    fig.suptitle("sweep: response surfaces")
    return fig


def scatter_matrix(meta, rows, swept):
    cols = responses(meta)[:6]
    fig, axes = plt.subplots(len(cols), len(swept), figsize=(3.2 * len(swept), 2.8 * len(cols)), squeeze=False)
    for i, col in enumerate(cols):
        for k, p in enumerate(swept):
            ax = axes[i][k]
            for j, (case, crows) in enumerate(by_case(meta, rows)):
                good = [(float(r[p]), num(r[col["header"]])) for r in crows if r["status"] in GOOD]
                good = [g for g in good if g[1] is not None]
                ax.plot([g[0] for g in good], [g[1] for g in good], ".", color=f"C{j}", label=case or None)
            mark_failures(ax, rows, p)
            if i == len(cols) - 1:
                ax.set_xlabel(p)
            if k == 0:
                ax.set_ylabel(col["header"], fontsize=8)
            ax.tick_params(labelsize=7)
    fig.suptitle("sweep: each output against each parameter")
    return fig


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else "."
    meta, rows = load(d)
    swept = [p["name"] for p in meta["parameters"] if "value" not in p]
    if not rows or not swept or not responses(meta):
        print("plot_sweep: nothing to plot in", d)
        return 0
    if len(swept) == 1:
        fig = curves(meta, rows, swept[0])
    elif len(swept) == 2:
        fig = surfaces(meta, rows, swept[0], swept[1])
    else:
        fig = scatter_matrix(meta, rows, swept)
    fig.tight_layout()
    fig.savefig(os.path.join(d, "sweep.png"), dpi=110)
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
