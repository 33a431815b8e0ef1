#!/usr/bin/env python3
"""PNG plots for the study report written by `flexsens study` (reads its CSV files)."""
import csv
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


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


def error_time(d, model):
    head, rows = read(os.path.join(d, f"error_time_{model}.csv"))
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    t = [float(r[0]) for r in rows]
    for j, label in enumerate(head[1:], start=1):
        pts = [(ti, num(r[j])) for ti, r in zip(t, rows) if num(r[j])]
        if pts:
            ax.semilogy([p[0] for p in pts], [p[1] for p in pts], label=label)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("|dz2/dp - reference|")
    ax.set_title(f"{model} five-bar: error of each method over time")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(d, f"error_time_{model}.png"), dpi=110)
    plt.close(fig)


def work_precision(d):
    head, rows = read(os.path.join(d, "work_precision.csv"))
    fig, ax = plt.subplots(figsize=(7, 4.2))
    groups = {}
    for model, integ, setting, cpu, err in rows:
        if num(cpu) and num(err):
            groups.setdefault(f"{model} {integ}", []).append((float(cpu), float(err), setting))
    for label, pts in groups.items():
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=label)
    ax.set_xlabel("CPU time [s]")
    ax.set_ylabel("error of dz2/dp at t = 1 s")
    ax.set_title("work-precision")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(d, "work_precision.png"), dpi=110)
    plt.close(fig)


def nd_sweep(d):
    head, rows = read(os.path.join(d, "nd_sweep.csv"))
    fig, ax = plt.subplots(figsize=(7, 4.2))
    h = [float(r[0]) for r in rows]
    for j, label in enumerate(head[1:], start=1):
        pts = [(hi, num(r[j])) for hi, r in zip(h, rows) if num(r[j])]
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=label.replace("_", " "))
    ax.set_xlabel("relative step h")
    ax.set_ylabel("|nd - dd| at t = 1 s")
    ax.set_title("finite-difference step: truncation against round-off")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(d, "nd_sweep.png"), dpi=110)
    plt.close(fig)


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else "bench/study"
    for model in ("rigid", "flexible"):
        error_time(d, model)
    work_precision(d)
    nd_sweep(d)
    print("plots written to", d)


if __name__ == "__main__":
    main()
