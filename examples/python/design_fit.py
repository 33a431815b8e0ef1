#!/usr/bin/env python3
"""A design fit with scipy: the stiffness k [N m/rad] and damping c [N m s/rad] of the spring at
the double pendulum's upper joint (examples/seed000/double_pendulum.yaml) that bring the
pendulum's tip height zT and upper angle z1 to targets at t = 2 s. Fitted twice with
scipy.optimize.minimize (BFGS, same tolerance): with the exact gradient from flexsens'
sensitivities (jac=True, one run per evaluation) and with finite-difference gradients (one run
per evaluation plus one per parameter). Prints the model runs and iterations of both.

    PYTHONPATH=build/python python3 examples/python/design_fit.py
"""
import pathlib
import sys
import time

import numpy as np
from scipy.optimize import minimize

import flexsens

SCENE = pathlib.Path(__file__).resolve().parents[1] / "seed000" / "double_pendulum.yaml"
T_TARGET = 2.0          # [s] when the tip must be there
TRUE_DESIGN = (2.5, 0.4)  # k, c of the run that made the targets: the fit must find them again
START = (1.0, 1.0)        # the scene's k and c
GTOL = 1e-8               # BFGS: stop when |gradient| falls below this


class Objective:
    """J(k, c) = 1/2 ((zT - zT*) / 1 m)^2 + 1/2 ((z1 - z1*) / 1 rad)^2 at t = T_TARGET, and its
    gradient from the runs' sensitivities dzT/dk, dzT/dc, dz1/dk, dz1/dc; counts the runs."""

    def __init__(self, scene, targets):
        self.scene, self.targets, self.runs = scene, targets, 0

    def outputs_at_target_time(self, design):
        k, c = design
        self.runs += 1
        result = self.scene.run(t_end=T_TARGET, parameters={"k": float(k), "c": float(c)})
        if result.status != "complete":
            raise RuntimeError(f"run at k = {k}, c = {c} is {result.status}: {result.reason}")
        return result, len(result) - 1  # the last frame is t = T_TARGET

    def value_and_gradient(self, design):
        result, f = self.outputs_at_target_time(design)
        value, gradient = 0.0, np.zeros(2)
        for output, target in self.targets.items():
            miss = result.outputs[output][f] - target
            value += 0.5 * miss ** 2
            gradient += miss * np.array([result.sensitivities[(output, p)][f] for p in ("k", "c")])
        return value, gradient

    def value(self, design):
        return self.value_and_gradient(design)[0]  # the sensitivities are left unused


def main():
    scene = flexsens.load(SCENE)
    probe = Objective(scene, {})
    truth, f = probe.outputs_at_target_time(TRUE_DESIGN)
    targets = {name: float(truth.outputs[name][f]) for name in ("zT", "z1")}
    print(f"targets at t = {T_TARGET} s: zT = {targets['zT']:.6f} m, z1 = {targets['z1']:.6f} rad "
          f"(made with k = {TRUE_DESIGN[0]}, c = {TRUE_DESIGN[1]})")
    rows = []
    for label, use_exact in (("exact sensitivities (jac=True)", True), ("finite differences", False)):
        objective = Objective(scene, targets)
        start = time.perf_counter()
        if use_exact:
            fit = minimize(objective.value_and_gradient, START, jac=True, method="BFGS", options={"gtol": GTOL})
        else:
            fit = minimize(objective.value, START, method="BFGS", options={"gtol": GTOL})  # scipy's 2-point step
        seconds = time.perf_counter() - start
        error = np.max(np.abs(fit.x - TRUE_DESIGN) / np.array(TRUE_DESIGN))
        rows.append((label, fit.nit, objective.runs, seconds, fit.fun, error, fit.success))
    print(f"{'gradient':32s} {'iterations':>10s} {'model runs':>10s} {'wall [s]':>9s} {'J':>10s} "
          f"{'design error':>12s}  converged")
    for label, nit, runs, seconds, value, error, success in rows:
        print(f"{label:32s} {nit:10d} {runs:10d} {seconds:9.2f} {value:10.2e} {error:12.2e}  {success}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
