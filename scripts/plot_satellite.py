#!/usr/bin/env python3
"""Figure 12 of the PIM paper for the satellite: dx_B2/dL_B1B2 over 10 s for SAT1 and SAT2
(BDF-1, dt = 0.02 s), next to the four panels' opening angles.
    python3 scripts/plot_satellite.py RESULTS_DIR   (reads RESULTS_DIR/satellite/SAT*/series.csv)
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
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.5))
    for case, style in (("SAT1", "-"), ("SAT2", "--")):
        d = read(runs[case])
        a.plot(d["t"], d["dxB2/dL_B1B2"], style, color="C0", label=case + ", dt = 0.02 s")
        # The same scheme with a 4x smaller step damps 4x less (BDF-1's numerical damping is
        # proportional to dt): the paper attributes the curves' convergence to that damping.
        fine = os.path.join(root, "satellite_dt0.005", case, "series.csv")
        if os.path.exists(fine):
            f = read(fine)
            a.plot(f["t"], f["dxB2/dL_B1B2"], style, color="C3", label=case + ", dt = 0.005 s")
        if case == "SAT1":
            for k in range(1, 5):
                b.plot(d["t"], [x * 180 / 3.141592653589793 for x in d["open%d" % k]], label="panel %d" % k)
    a.set_xlabel("t [s]")
    a.set_ylabel("dx_B2 / dL_B1B2  [m/m]")
    a.set_title("dx_B2/dL_B1B2, BDF-1 (fig. 12; smaller dt = less damping)")
    a.legend()
    a.grid(True, alpha=0.3)
    b.set_xlabel("t [s]")
    b.set_ylabel("opening angle [deg]")
    b.set_title("Panel opening angles (SAT1 nominal motion)")
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
