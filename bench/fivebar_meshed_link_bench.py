#!/usr/bin/env python3
"""Five-bar: link 1-2 as a two-segment beam (examples/fivebar/flexible.yaml) against the same
link as a meshed plate (examples/fivebar/meshed_link.yaml: same length, mass and EI), cases
F1, F4 and their F-R twins, trapezoidal rule dt = 1 ms to 2 s. Table of z2 and dz2/dp at
0.5, 1, 1.5, 2 s. Writes bench/fivebar_meshed_link/bench.md (not a test).

    python3 bench/fivebar_meshed_link_bench.py [--flexsens build/flexsens] [--work DIR]
    (--work: reuse the runs already in DIR/beam, DIR/meshed, DIR/meshed4 when present)
"""
import argparse, csv, os, re, subprocess, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "bench", "fivebar_meshed_link")
EX = os.path.join(ROOT, "examples", "fivebar")


def prepare(wd):
    beam = open(os.path.join(EX, "flexible.yaml")).read().replace("frame_interval: 0.01", "frame_interval: 0.1")
    mesh = open(os.path.join(EX, "meshed_link.yaml")).read().replace("frame_interval: 0.01", "frame_interval: 0.1")
    mesh = mesh.replace("mesh: meshed_link.geo", "mesh: " + os.path.join(EX, "meshed_link.geo"))
    mesh = mesh.replace("\noutput:", "\noutput:\n  vtk: false")
    open(os.path.join(wd, "beam.yaml"), "w").write(beam)
    open(os.path.join(wd, "meshed.yaml"), "w").write(mesh)


def run(exe, wd, scene, cases, out):
    if all(os.path.exists(os.path.join(wd, out, c, "series.csv")) for c in cases):
        return
    cmd = [exe, "run", os.path.join(wd, scene), "--t-end", "2", "--out", os.path.join(wd, out)]
    for c in cases:
        cmd += ["--case", c]
    subprocess.run(cmd, check=True, capture_output=True)


def load(path):
    return {round(float(r["t"]), 3): r for r in csv.DictReader(open(path))}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexsens", default=os.path.join(ROOT, "build", "flexsens"))
    ap.add_argument("--work")
    a = ap.parse_args()
    wd = a.work or tempfile.mkdtemp(prefix="fivebar_meshed_")
    prepare(wd)
    run(a.flexsens, wd, "beam.yaml", ["F1", "F1R", "F4", "F4R"], "beam")
    run(a.flexsens, wd, "meshed.yaml", ["F1", "F1R"], "meshed")
    run(a.flexsens, wd, "meshed.yaml", ["F4", "F4R"], "meshed4")
    lines = ["# Five-bar: beam link against meshed-plate link (bench/fivebar_meshed_link_bench.py)", "",
             "Trapezoidal rule, dt = 1 ms. Beam: 2 positions-only segments, E = 206.94 GPa, side 0.01031 m.",
             "Plate: 6-node triangles (size 0.025 m, 1496 coordinates), width 0.05 m, thickness 2.1259 mm,",
             "E = 8.7988 GPa, nu = 0.2838: same length, mass (1.5 kg) and EI (194.85 N m^2).", "",
             "| case | t [s] | z2 beam [m] | z2 plate [m] | dz2/dp beam | dz2/dp plate | rel. diff. dz2/dp |",
             "|---|---|---|---|---|---|---|"]
    for case, mdir in [("F1", "meshed"), ("F1R", "meshed"), ("F4", "meshed4"), ("F4R", "meshed4")]:
        pb, pm = os.path.join(wd, "beam", case, "series.csv"), os.path.join(wd, mdir, case, "series.csv")
        if not (os.path.exists(pb) and os.path.exists(pm)):
            continue
        b, m = load(pb), load(pm)
        key = [k for k in b[0.5] if k.startswith("dz2/")][0]
        for t in (0.5, 1.0, 1.5, 2.0):
            db, dm = float(b[t][key]), float(m[t][key])
            lines.append("| %s (%s) | %.1f | %.6f | %.6f | %+.5f | %+.5f | %.1e |" % (
                case, key[4:], t, float(b[t]["z2"]), float(m[t]["z2"]), db, dm, abs(dm - db) / abs(db)))
    open(os.path.join(OUT, "bench.md"), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
