"""Shared helpers of the Python API's tests: where the CLI and the sources are (CTest sets
FLEXSENS_EXE and FLEXSENS_SOURCE_DIR; by hand the defaults fit a build in build/), running the
CLI, and reading its series.csv, the reference the module's results are compared with."""
import csv
import os
import pathlib
import subprocess

import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("FLEXSENS_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
EXE = pathlib.Path(os.environ.get("FLEXSENS_EXE", SOURCE_DIR / "build" / "flexsens"))
FIVEBAR_FLEXIBLE = SOURCE_DIR / "examples" / "fivebar" / "flexible.yaml"
FIVEBAR_RIGID = SOURCE_DIR / "examples" / "fivebar" / "rigid.yaml"
PENDULUM = SOURCE_DIR / "examples" / "pendulum" / "pendulum.yaml"


def run_cli(*args, cwd=None):
    """Runs `flexsens ARGS`; returns the finished process (output captured, not checked)."""
    return subprocess.run([str(EXE), *map(str, args)], cwd=cwd, capture_output=True, text=True, check=False)


def read_series(path):
    """series.csv as a dict column -> numpy array (the CLI's 15 significant digits)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, values = rows[0], np.array(rows[1:], dtype=float)
    return {name: values[:, i] for i, name in enumerate(header)}


def files_below(folder):
    """Every file and folder below `folder`, as paths relative to it."""
    folder = pathlib.Path(folder)
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def assert_close_to_scale(actual, expected, rtol, what):
    """|actual - expected| <= rtol max|expected| at every frame: relative to the column's scale,
    so that values crossing zero are held to the same absolute accuracy."""
    actual, expected = np.asarray(actual), np.asarray(expected)
    assert actual.shape == expected.shape, what
    scale = max(np.max(np.abs(expected)), 1e-300)
    worst = np.max(np.abs(actual - expected)) / scale
    assert worst <= rtol, f"{what}: largest difference {worst:.3e} of max |value| {scale:.3e} (allowed {rtol:g})"


@pytest.fixture(scope="session")
def flexsens_module():
    import flexsens
    return flexsens
