#!/usr/bin/env python3
"""Right-angle cantilever (examples/frames/right_angle_cantilever.yaml) against the digitized
published tip history: runs flexsens, prints the extremes of both curves and the largest
difference, and plots both (PNG). Usage: right_angle_cantilever.py FLEXSENS OUTDIR [PNG]"""
import bisect, csv, os, subprocess, sys

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "..", "examples", "frames", "right_angle_cantilever.yaml")


def read(path, tcol, zcol):
    with open(path) as f:
        rows = [r for r in csv.reader(l for l in f if not l.startswith("#"))]
    head = [h.strip() for h in rows[0]]
    i, j = head.index(tcol), head.index(zcol)
    return [float(r[i]) for r in rows[1:]], [float(r[j]) for r in rows[1:]]


def extremes(t, z):
    return [(t[i], z[i]) for i in range(1, len(z) - 1) if (z[i] - z[i - 1]) * (z[i + 1] - z[i]) < 0 and abs(z[i]) > 1]


def main():
    flexsens, out = sys.argv[1], sys.argv[2]
    png = sys.argv[3] if len(sys.argv) > 3 else None
    run = subprocess.run([flexsens, "run", SCENE, "--out", out], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(run.stderr)
    t, z = read(os.path.join(out, "series.csv"), "t", "tip_z")
    tr, zr = read(os.path.join(HERE, "simo_vuquoc_tip.csv"), "t", "z")
    at = lambda s: z[min(bisect.bisect_left(t, s), len(t) - 1)]
    worst = max(abs(at(s) - v) for s, v in zip(tr, zr))
    print("flexsens extremes (t, z):", [(round(a, 2), round(b, 3)) for a, b in extremes(t, z)])
    print("published extremes (t, z):", [(round(a, 2), round(b, 3)) for a, b in extremes(tr, zr)])
    print(f"largest |z - z_published| at the published points: {worst:.3f}")
    if png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(7, 3.8))
        ax.plot(t, z, label="flexsens, ancf_beam 2 x 10 elements, generalized-alpha dt 0.01")
        ax.plot(tr, zr, "o", ms=3, label="Simo & Vu-Quoc 1988 (digitized)")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("tip out-of-plane displacement")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(png, dpi=110)


if __name__ == "__main__":
    main()
