#!/usr/bin/env python3
"""The flexible five-bar's sensitivity dz2/dL_A1 (the PIM paper's figure 7) from Python: each
PIM case F1-F3 (how the perturbed mechanism starts) beside its rigid twin F1R-F3R (the beam
modelled rigid), plotted with matplotlib into a PNG.

    PYTHONPATH=build/python python3 examples/python/fivebar_sensitivity_plot.py [--t-end 5] [--png FILE]
"""
import argparse
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt

import flexsens

SCENE = pathlib.Path(__file__).resolve().parents[1] / "fivebar" / "flexible.yaml"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--t-end", type=float, default=5.0, help="simulated time [s] (scene: 5)")
    parser.add_argument("--png", default="fivebar_dz2_dLA1.png", help="picture to write")
    args = parser.parse_args()

    scene = flexsens.load(SCENE)
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for case, colour in (("F1", "C0"), ("F2", "C1"), ("F3", "C2")):
        for name, style in ((case, "-"), (case + "R", "--")):
            result = scene.run(case=name, t_end=args.t_end)  # nothing written: the arrays are all we need
            ax.plot(result.t, result.sensitivities[("z2", "L_A1")], style, color=colour,
                    label=f"{name} ({result.status})")
            print(f"{name}: {len(result)} frames, max |dz2/dL_A1| = "
                  f"{abs(result.sensitivities[('z2', 'L_A1')]).max():.4g}, {result.status}")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("dz2/dL_A1 [m/m]")
    ax.set_title("Flexible five-bar: solid = flexible beam, dashed = rigid twin")
    ax.grid(True, alpha=0.3)
    ax.legend(ncol=3, fontsize=8)
    fig.tight_layout()
    fig.savefig(args.png, dpi=120)
    print(f"written {args.png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
