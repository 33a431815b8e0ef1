#!/usr/bin/env python3
"""Figure 12 of the PIM paper for the satellite: dx_B2/dL_B1B2 over 10 s for SAT1 and SAT2
with BDF-1 (dt = 0.02 s, the paper's run) and, side by side, with generalized-alpha (rho_inf 0.5,
dt = 1 ms: no numerical damping of the panels' motion), next to panel 1's opening angle.
    python3 scripts/plot_satellite.py RESULTS_DIR
reads RESULTS_DIR/satellite/SAT*/series.csv and RESULTS_DIR/satellite_galpha/SAT*/series.csv.
"""
import csv, os, sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "results"
    runs = {c: os.path.join(root, "satellite", c, "series.csv") for c in ("SAT1", "SAT2")}
    missing = [p for p in runs.values() if not os.path.exists(p)]
    if missing:
        sys.exit("plot_satellite: missing %s (run examples/satellite/satellite.yaml first)" % ", ".join(missing))
    fig, (a, g, b) = plt.subplots(1, 3, figsize=(17, 4.5))
    galpha = {c: os.path.join(root, "satellite_galpha", c, "series.csv") for c in ("SAT1", "SAT2")}
    for case, style in (("SAT1", "-"), ("SAT2", "--")):
        d = read(runs[case])
        a.plot(d["t"], d["dxB2/dL_B1B2"], style, color="C0", label=case)
        if case == "SAT1":
            b.plot(d["t"], [x * 180 / 3.141592653589793 for x in d["open1"]], color="C0", label="BDF-1, dt = 0.02 s")
        if os.path.exists(galpha[case]):
            f = read(galpha[case])
            g.plot(f["t"], f["dxB2/dL_B1B2"], style, color="C3", label=case)
            if case == "SAT1":
                b.plot(f["t"], [x * 180 / 3.141592653589793 for x in f["open1"]], color="C3",
                       label="generalized-alpha, dt = 1 ms")
    a.set_title("BDF-1, dt = 0.02 s (paper): the initial gap of 4 is damped")
    g.set_title("generalized-alpha, rho_inf 0.5, dt = 1 ms: no damping, growth to ~1e7")
    g.set_yscale("symlog", linthresh=1.0)  # grows to ~1e7: no numerical damping holds it
    for ax in (a, g):
        ax.set_xlabel("t [s]")
        ax.set_ylabel("dx_B2 / dL_B1B2  [m/m]")
        ax.legend()
        ax.grid(True, alpha=0.3)
    b.set_xlabel("t [s]")
    b.set_ylabel("opening angle of panel 1 [deg]")
    b.set_title("Panel 1 opening (nominal motion)")
    b.axhline(90, color="k", lw=0.5)
    b.legend()
    b.grid(True, alpha=0.3)
    fig.tight_layout()
    out = os.path.join(root, "plots")
    os.makedirs(out, exist_ok=True)
    fig.savefig(os.path.join(out, "fig12_satellite.png"), dpi=110)
    print("plot_satellite: %s" % os.path.join(out, "fig12_satellite.png"))


if __name__ == "__main__":
    main()
