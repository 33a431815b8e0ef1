#!/usr/bin/env python3
"""Writes fivebar_path_x.csv and fivebar_path_z.csv beside fivebar_path.yaml: the path of point 2
of the rigid five-bar with L_A1 = 1.5 m and L_3B = 1.3 m, one row per step (t, value), by the
Python module (build/python):
   PYTHONPATH=build/python python3 examples/optimize/make_fivebar_path.py
"""
import os

import flexsens

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    scene = flexsens.load(os.path.join(HERE, "fivebar_path.yaml"))
    result = scene.run(parameters={"L_A1": 1.5, "L_3B": 1.3})
    for name, column in (("x", "x2"), ("z", "z2")):
        with open(os.path.join(HERE, "fivebar_path_%s.csv" % name), "w") as f:
            f.write("# t [s], %s of point 2 [m] with L_A1 = 1.5 m, L_3B = 1.3 m (make_fivebar_path.py)\n" % name)
            for t, v in zip(result.t, result.outputs[column]):
                f.write("%.17g,%.17g\n" % (t, v))


if __name__ == "__main__":
    main()
