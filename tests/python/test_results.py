"""Results through Python are the CLI's: examples/fivebar/flexible.yaml case F1 against the
CLI's series.csv (acceptance: 1e-12 of each column's scale), the state arrays against the
outputs they hold, out=DIR writes what the CLI writes, out=None writes nothing."""
import json
import os

import numpy as np
import pytest

from conftest import FIVEBAR_FLEXIBLE, FIVEBAR_RIGID, assert_close_to_scale, files_below, read_series, run_cli


@pytest.fixture(scope="module")
def f1_cli(tmp_path_factory):
    out = tmp_path_factory.mktemp("cli") / "out"
    proc = run_cli("run", FIVEBAR_FLEXIBLE, "--case", "F1", "--out", out)
    assert proc.returncode == 0, proc.stderr
    return out / "F1"


@pytest.fixture(scope="module")
def f1_python(flexsens_module):
    return flexsens_module.load(FIVEBAR_FLEXIBLE).run(case="F1")


def test_f1_every_series_column_equals_the_cli(f1_cli, f1_python):
    cli = read_series(f1_cli / "series.csv")
    assert list(cli) == list(f1_python.series)
    assert len(f1_python) == len(cli["t"]) == 501
    for name, column in cli.items():
        assert_close_to_scale(f1_python.series[name], column, 1e-12, name)
    assert_close_to_scale(f1_python.outputs["z2"], cli["z2"], 1e-12, "z2")
    assert_close_to_scale(f1_python.sensitivities[("z2", "L_A1")], cli["dz2/dL_A1"], 1e-12, "dz2/dL_A1")
    assert_close_to_scale(f1_python.energy["total"], cli["energy_J"], 1e-12, "energy_J")


def test_f1_summary_is_the_cli_summary(f1_cli, f1_python):
    cli = json.loads((f1_cli / "summary.json").read_text())
    assert f1_python.status == cli["status"] == "complete"
    assert f1_python.reason == ""
    for key in ("t_reached", "frames", "case", "statistics", "coordinates", "parameters", "n", "m"):
        if key == "statistics":  # wall times differ, the counts do not
            cli[key].pop("factorization_seconds")
            f1_python.summary[key].pop("factorization_seconds")
        assert f1_python.summary[key] == cli[key], key


def test_state_arrays_hold_the_outputs(f1_python):
    # z2 is the coordinate z(n2): the state arrays must carry the same numbers as the outputs.
    result = f1_python
    frames, n = len(result), len(result.coordinates)
    assert result.q.shape == result.v.shape == (frames, n)
    assert result.dq.shape == result.dv.shape == (frames, n, 1)
    z2 = result.coordinates.index("z(n2)")
    np.testing.assert_array_equal(result.q[:, z2], result.outputs["z2"])
    np.testing.assert_array_equal(result.dq[:, z2, 0], result.sensitivities[("z2", "L_A1")])
    assert result.q.flags["C_CONTIGUOUS"] and not result.q.flags["WRITEABLE"]
    assert result.q.base is not None  # a view into the Result, not a copy


def test_out_dir_writes_what_the_cli_writes(flexsens_module, tmp_path):
    scene = flexsens_module.load(FIVEBAR_RIGID)
    cli, py = tmp_path / "cli", tmp_path / "py"
    assert run_cli("run", FIVEBAR_RIGID, "--case", "R1", "--t-end", "0.2", "--out", cli).returncode == 0
    result = scene.run(case="R1", t_end=0.2, out=py)
    assert result.directory == str(py / "R1")
    assert files_below(py) == files_below(cli)
    assert (py / "R1" / "series.csv").read_bytes() == (cli / "R1" / "series.csv").read_bytes()
    assert (py / "R1" / "frames.pvd").read_bytes() == (cli / "R1" / "frames.pvd").read_bytes()


def test_without_out_nothing_is_written(flexsens_module, tmp_path, monkeypatch):
    # The scene's output.directory is relative to the working directory: run from an empty one.
    monkeypatch.chdir(tmp_path)
    before = files_below(FIVEBAR_RIGID.parent)
    result = flexsens_module.load(FIVEBAR_RIGID).run(case="R1", t_end=0.2)
    assert result.directory is None
    assert result.summary["files"] == []
    assert files_below(tmp_path) == []
    assert files_below(FIVEBAR_RIGID.parent) == before


def test_parameter_values_leave_the_scene_unchanged(flexsens_module):
    scene = flexsens_module.load(FIVEBAR_RIGID)
    nominal = dict(scene.parameters)
    first = scene.run(case="R1", t_end=0.2)
    moved = scene.run(case="R1", t_end=0.2, parameters={"L_A1": nominal["L_A1"] * 1.01})
    again = scene.run(case="R1", t_end=0.2)
    assert scene.parameters == nominal
    assert moved.parameters["L_A1"] == nominal["L_A1"] * 1.01
    assert again.parameters["L_A1"] == nominal["L_A1"]
    assert not np.array_equal(moved.outputs["z2"], first.outputs["z2"])
    np.testing.assert_array_equal(again.series["z2"], first.series["z2"])
    np.testing.assert_array_equal(again.dq, first.dq)
