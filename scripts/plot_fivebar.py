#!/usr/bin/env python3
"""PNG plots of dz2/dp versus time for the five-bar study, in the manner of the PIM paper's
figures 4 (rigid R1-R3), 7 (F1-F3 with their F-R twins) and 9 (F4-F6 with twins).
Reads results/fivebar_rigid/<case>/series.csv and results/fivebar_flexible/<case>/series.csv."""
import csv
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def series(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    head, data = rows[0], rows[1:]
    col = next(i for i, h in enumerate(head) if h.startswith("dz2/d"))
    return [float(r[0]) for r in data], [float(r[col]) for r in data], head[col]


def figure(root, cases, title, out, twins=False):
    fig, ax = plt.subplots(figsize=(7, 4))
    drawn = 0
    for i, c in enumerate(cases):
        for name, style in [(c, "-")] + ([(c + "R", "--")] if twins else []):
            path = os.path.join(root, name, "series.csv")
            if not os.path.exists(path):
                continue
            t, d, label = series(path)
            ax.plot(t, d, style, color=f"C{i}", label=name if style == "-" else name + " (beam rigid)")
            drawn += 1
    if not drawn:
        plt.close(fig)
        return None
    ax.set_xlabel("time [s]")
    ax.set_ylabel(label)
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return out


def main():
    results = sys.argv[1] if len(sys.argv) > 1 else "results"
    out = os.path.join(results, "plots")
    os.makedirs(out, exist_ok=True)
    made = [
        figure(os.path.join(results, "fivebar_rigid"), ["R1", "R2", "R3"],
               "Rigid five-bar: dz2/dL_A1 (paper fig. 4)", os.path.join(out, "fig4_rigid.png")),
        figure(os.path.join(results, "fivebar_flexible"), ["F1", "F2", "F3"],
               "Flexible five-bar: dz2/dL_A1, F and F-R (paper fig. 7)", os.path.join(out, "fig7_flexible_LA1.png"), True),
        figure(os.path.join(results, "fivebar_flexible"), ["F4", "F5", "F6"],
               "Flexible five-bar: dz2/dL_B1, F and F-R (paper fig. 9)", os.path.join(out, "fig9_flexible_LB1.png"), True),
    ]
    for m in made:
        if m:
            print("plot written:", m)


if __name__ == "__main__":
    main()
