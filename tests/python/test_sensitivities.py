"""The sensitivities a run returns are the derivatives of the runs: central differences of two
Scene.run(parameters=...) calls, computed here, match them (acceptance: the flexible five-bar's
case F1, 1e-5 of each column's scale). Runs at other parameter values start where the PIM case
puts the perturbed mechanism, so the differences include the initial sensitivities."""
import numpy as np

from conftest import FIVEBAR_FLEXIBLE, PENDULUM, assert_close_to_scale

# Of |p|: F1's difference from the sensitivities is 2e-4 of the scale at 1e-3, 2e-6 at 1e-4,
# 6e-8 at 1e-5 (truncation, ~ step^2), 4e-7 at 1e-6 (Newton's tolerance / step).
RELATIVE_STEP = 1e-5


def central_difference(scene, case, name, column_of, **options):
    """(run at p + h) - (run at p - h) over 2h for the arrays column_of(result) picks."""
    p = scene.parameters[name]
    h = RELATIVE_STEP * abs(p)
    plus = scene.run(case=case, parameters={name: p + h}, **options)
    minus = scene.run(case=case, parameters={name: p - h}, **options)
    return (column_of(plus) - column_of(minus)) / (2 * h)


def test_f1_sensitivities_equal_central_differences_of_runs(flexsens_module):
    scene = flexsens_module.load(FIVEBAR_FLEXIBLE)
    nominal = scene.run(case="F1")
    fd = central_difference(scene, "F1", "L_A1", lambda r: r.outputs["z2"])
    assert_close_to_scale(nominal.sensitivities[("z2", "L_A1")], fd, 1e-5, "dz2/dL_A1")
    fd_q = central_difference(scene, "F1", "L_A1", lambda r: r.q)
    assert_close_to_scale(nominal.dq[:, :, 0], fd_q, 1e-5, "dq/dL_A1")


def test_pendulum_sensitivities_to_two_parameters(flexsens_module):
    # Two parameters of one case, a length and a mass: each difference changes one of them.
    scene = flexsens_module.load(PENDULUM)
    nominal = scene.run(t_end=0.5)
    assert nominal.dq.shape[2] == 2
    for k, name in enumerate(["L", "m"]):
        fd = central_difference(scene, None, name, lambda r: r.q, t_end=0.5)
        scale = max(np.max(np.abs(fd)), 1.0)  # the mass moves nothing: dq/dm is round-off
        assert np.max(np.abs(nominal.dq[:, :, k] - fd)) <= 1e-5 * scale, name


def test_runs_at_other_values_start_where_the_case_says(flexsens_module):
    # Case same_angle keeps the bar's angle: a 10% longer bar starts with its tip 10% further out.
    scene = flexsens_module.load(PENDULUM)
    longer = scene.run(t_end=0.02, parameters={"L": 1.1})
    assert abs(longer.outputs["tip_x"][0] - 1.1) < 1e-12
    assert abs(longer.outputs["tip_y"][0]) < 1e-12


def test_two_parameters_changed_at_once_move_the_run_by_both_sensitivities(flexsens_module):
    # q(p0 + d) - q(p0) = dq/dp . d + O(|d|^2): both values applied together, the run moves by
    # the sum of the two first-order changes (a length and a mass; the mass moves nothing).
    scene = flexsens_module.load(PENDULUM)
    nominal = scene.run(t_end=0.5)
    p0 = scene.parameters
    step = {"L": 1e-4 * p0["L"], "m": 1e-4 * p0["m"]}
    moved = scene.run(t_end=0.5, parameters={name: p0[name] + step[name] for name in p0})
    first_order = nominal.dq[:, :, 0] * step["L"] + nominal.dq[:, :, 1] * step["m"]
    remainder = moved.q - nominal.q - first_order
    assert np.max(np.abs(remainder)) <= 1e-3 * np.max(np.abs(first_order))  # measured: 6e-5
