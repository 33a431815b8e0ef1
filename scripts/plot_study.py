#!/usr/bin/env python3
"""PNG plots for the study report written by `flexsens study` (reads its CSV files)."""
import csv
import glob
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# model key -> (title, studied sensitivity, output)
MODELS = {
    "rigid": ("rigid five-bar (R1)", "dz2/dL_A1", "z2"),
    "flexible": ("flexible five-bar (F1)", "dz2/dL_A1", "z2"),
    "four_bar": ("3D four-bar (seed 000)", "dz4/dm", "z4"),
    "double_pendulum": ("3D double pendulum (seed 000)", "dz2/dm", "z2"),
}
STYLES = ["-", "--", "-.", ":"]
# error over time: colour per integrator, line style per method (ad is drawn wide and dotted
# under dd: they agree to round-off)
COLORS = {"trapezoidal": "C0", "bdf1": "C1", "maggi_rk4": "C2", "idas": "C3", "generalized_alpha": "C4"}
METHOD_STYLE = {"dd": {"ls": "-"}, "ad": {"ls": ":"}, "nd": {"ls": "--"}, "nd-forward": {"ls": "-."},
                "dq": {"ls": (0, (1, 3))}}


def read(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def num(x):
    try:
        v = float(x)
        return v if math.isfinite(v) and v > 0 else None
    except ValueError:
        return None


def model_info(key):
    return MODELS.get(key, (key, "d(output)/dp", "output"))


def cost(d):
    head, rows = read(os.path.join(d, "cost.csv"))
    col = {h: i for i, h in enumerate(head)}
    panels = {}
    for r in rows:
        panels.setdefault((r[col["model"]], r[col["integrator"]], r[col["dt"]]), {}).setdefault(
            r[col["method"]], []).append((int(r[col["parameters"]]), float(r[col["ratio"]])))
    n = len(panels)
    ncol = 2
    nrow = (n + ncol - 1) // ncol
    fig, axes = plt.subplots(nrow, ncol, figsize=(10, 3.2 * nrow), squeeze=False)
    for ax, ((model, integ, dt), methods) in zip(axes.flat, panels.items()):
        for j, (method, pts) in enumerate(methods.items()):
            ax.semilogy([p[0] for p in pts], [p[1] for p in pts], "o" + STYLES[j % 4], label=method)
        ax.set_title(f"{model_info(model)[0]}, {integ} dt = {float(dt) * 1e3:g} ms", fontsize=9)
        ax.set_xlabel("number of parameters")
        ax.set_ylabel("total / dynamics")
        ax.set_xticks([1, 2, 3, 4])
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    fig.suptitle("cost of sensitivities: CPU time of dynamics + sensitivities over dynamics alone")
    fig.tight_layout()
    fig.savefig(os.path.join(d, "cost.png"), dpi=110)
    plt.close(fig)


def error_time(d, path):
    model = os.path.basename(path)[len("error_time_"):-len(".csv")]
    title, sens, _ = model_info(model)
    head, rows = read(path)
    fig, ax = plt.subplots(figsize=(9, 6))
    t = [float(r[0]) for r in rows]
    for j, label in enumerate(head[1:], start=1):
        pts = [(ti, num(r[j])) for ti, r in zip(t, rows) if num(r[j])]
        if pts:
            integ, method = label.split()[:2]
            ax.semilogy([p[0] for p in pts], [p[1] for p in pts], color=COLORS.get(integ, "k"),
                        lw=2.6 if method == "ad" else 1.3, label=label, **METHOD_STYLE.get(method, {}))
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"|{sens} - reference|")
    ax.set_title(f"{title}: error over time (reference: IDAS rtol 1e-10)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.13))
    fig.tight_layout()
    fig.savefig(os.path.join(d, f"error_time_{model}.png"), dpi=110)
    plt.close(fig)


def work_precision(d):
    head, rows = read(os.path.join(d, "work_precision.csv"))
    col = {h: i for i, h in enumerate(head)}
    groups = {}
    for r in rows:
        groups.setdefault((r[col["model"]], r[col["integrator"]]), []).append(
            (num(r[col["cpu_s"]]), num(r[col["value_error"]]), num(r[col["error"]]), r[col["t"]]))
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    models = list(dict.fromkeys(m for m, _ in groups))
    markers = "os^vD<>"
    for j, ((model, integ), pts) in enumerate(groups.items()):
        _, sens, out = model_info(model)
        tp = f"{float(pts[0][3]):g} s"
        mk = markers[models.index(model) % len(markers)]
        ls = STYLES[models.index(model) % 4]
        for ax, k in ((axes[0], 1), (axes[1], 2)):
            good = [(p[0], p[k]) for p in pts if p[0] and p[k]]
            if good:
                ax.loglog([p[0] for p in good], [p[1] for p in good], mk + ls,
                          label=f"{model} {integ} ({out}, {sens} at {tp})")
    axes[0].set_ylabel("error of the output")
    axes[1].set_ylabel("error of its sensitivity")
    for ax in axes:
        ax.set_xlabel("CPU time [s]")
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=6.5)
    fig.suptitle("work-precision (reference IDAS rtol 1e-12; flexible segments: N = 32)")
    fig.tight_layout()
    fig.savefig(os.path.join(d, "work_precision.png"), dpi=110)
    plt.close(fig)


def nd_sweep(d):
    head, rows = read(os.path.join(d, "nd_sweep.csv"))
    models = list(dict.fromkeys(r[0] for r in rows))
    fig, axes = plt.subplots(1, len(models), figsize=(6 * len(models), 4.4), squeeze=False)
    for ax, model in zip(axes.flat, models):
        mrows = [r for r in rows if r[0] == model]
        h = [float(r[2]) for r in mrows]
        for j, label in enumerate(head[3:], start=3):
            pts = [(hi, num(r[j])) for hi, r in zip(h, mrows) if num(r[j])]
            if pts:
                ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o" + STYLES[(j - 3) % 4], label=label)
        title, sens, _ = model_info(model)
        tp = f"{float(mrows[0][1]):g} s"
        ax.set_xlabel("relative step h")
        ax.set_ylabel(f"|nd - dd| of {sens} at t = {tp}")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("finite-difference step: truncation against round-off")
    fig.tight_layout()
    fig.savefig(os.path.join(d, "nd_sweep.png"), dpi=110)
    plt.close(fig)


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else "bench/study"
    cost(d)
    for path in sorted(glob.glob(os.path.join(d, "error_time_*.csv"))):
        error_time(d, path)
    work_precision(d)
    nd_sweep(d)
    print("plots written to", d)


if __name__ == "__main__":
    main()
