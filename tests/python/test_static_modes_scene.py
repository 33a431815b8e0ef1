"""Scene's description equals what the CLI says (check, summary.json), Scene.static equals
`flexsens static`, Scene.modes equals `flexsens modes --json` and a pendulum's analytic mode."""
import json
import math
import re

import numpy as np
import yaml

from conftest import FIVEBAR_FLEXIBLE, SOURCE_DIR, assert_close_to_scale, read_series, run_cli

SHAFT = SOURCE_DIR / "examples" / "ancf" / "beam3d_shaft.yaml"


def test_scene_describes_itself_as_the_cli_does(flexsens_module, tmp_path):
    scene = flexsens_module.load(FIVEBAR_FLEXIBLE)
    written = yaml.safe_load(FIVEBAR_FLEXIBLE.read_text())
    assert scene.cases == [c["name"] for c in written["cases"]]
    assert scene.outputs == [o["name"] for o in written["outputs"]]
    assert scene.integrator["type"] == written["integrator"]["type"]
    assert scene.integrator["t_end"] == written["integrator"]["t_end"]
    # Nominal values: lengths bound to the initial geometry (sqrt 2 m, sqrt 5 m).
    assert scene.parameters == {"L_A1": math.sqrt(2.0), "L_B1": math.sqrt(5.0)}
    check = run_cli("check", FIVEBAR_FLEXIBLE)
    assert check.returncode == 0, check.stderr
    sizes = re.search(r"n = (\d+) coordinates, m = (\d+) constraint equations, d = (\d+)", check.stdout)
    counts = scene.counts
    assert (counts["n"], counts["m"], counts["d"]) == tuple(map(int, sizes.groups()))
    for name, mr, ds in re.findall(r"case (\w+): .*?m_r = (\d+) .*?d_s = (\d+) SDOFs", check.stdout):
        assert (counts["cases"][name]["m_r"], counts["cases"][name]["d_s"]) == (int(mr), int(ds)), name
    assert len(counts["cases"]) == len(scene.cases) == 12


def test_static_equals_the_cli(flexsens_module, tmp_path):
    assert run_cli("static", SHAFT, "--out", tmp_path / "cli").returncode == 0
    cli = read_series(tmp_path / "cli" / "series.csv")
    result = flexsens_module.load(SHAFT).static()
    assert list(result.series) == list(cli) and result.status == "complete"
    for name, column in cli.items():
        assert_close_to_scale(result.series[name], column, 1e-12, name)
    np.testing.assert_array_equal(result.t, [0.5, 1.0])
    assert result.energy is None and result.dq.shape == (2, len(result.coordinates), 5)
    y = result.coordinates.index("y(tip)")
    np.testing.assert_array_equal(result.q[:, y], result.outputs["y_tip"])


def test_static_with_a_parameter_value_is_the_scene_with_that_value(flexsens_module, tmp_path):
    stiffer = SHAFT.read_text().replace("E: 2.0e11", "E: 2.2e11")
    (tmp_path / "stiffer.yaml").write_text(stiffer)
    assert run_cli("static", tmp_path / "stiffer.yaml", "--out", tmp_path / "cli").returncode == 0
    cli = read_series(tmp_path / "cli" / "series.csv")
    result = flexsens_module.load(SHAFT).static(parameters={"E": 2.2e11})
    assert_close_to_scale(result.outputs["y_tip"], cli["y_tip"], 1e-12, "y_tip")
    assert_close_to_scale(result.sensitivities[("y_tip", "E")], cli["dy_tip/dE"], 1e-12, "dy_tip/dE")


def test_modes_equal_the_cli(flexsens_module):
    cli = run_cli("modes", FIVEBAR_FLEXIBLE, "--count", "3", "--json")
    assert cli.returncode == 0, cli.stderr
    listed = json.loads(cli.stdout)
    modes = flexsens_module.load(FIVEBAR_FLEXIBLE).modes(3)
    expected = listed["lowest"] + listed["highest"]
    assert modes.indices == [m["index"] for m in expected]
    np.testing.assert_allclose(modes.frequencies, [m["hz"] for m in expected], rtol=1e-9)
    assert [p[0]["part"] for p in modes.parts] == [m["parts"][0]["part"] for m in expected]
    assert modes.shapes.shape == (len(expected), len(modes.coordinates))


HANGING_PENDULUM = """
dimension: 2
gravity: [0, -9.81]
nodes:
  - {name: A,   position: [0, 0], ground: true}
  - {name: tip, position: [0, -2]}
elements:
  - {name: bar, type: rigid_bar, nodes: [A, tip], mass: 3.0}
integrator: {type: trapezoidal, t_end: 1.0, dt: 0.01}
"""


def test_modes_of_a_hanging_bar_are_analytic(flexsens_module):
    # Uniform bar (m = 3 kg, L = 2 m) hanging from a hinge: omega^2 = 3 g / (2 L); the tip
    # swings horizontally, and with the tip's mass m / 3 the shape x^T M x = 1 has |x| = 1 m.
    modes = flexsens_module.loads(HANGING_PENDULUM).modes(1)
    assert len(modes) == 1
    np.testing.assert_allclose(modes.omega[0] ** 2, 3 * 9.81 / (2 * 2.0), rtol=1e-9)
    np.testing.assert_allclose(modes.frequencies[0], math.sqrt(3 * 9.81 / 4.0) / (2 * math.pi), rtol=1e-9)
    x, y = modes.coordinates.index("x(tip)"), modes.coordinates.index("y(tip)")
    np.testing.assert_allclose(abs(modes.shapes[0, x]), 1.0, rtol=1e-9)
    assert abs(modes.shapes[0, y]) < 1e-9
