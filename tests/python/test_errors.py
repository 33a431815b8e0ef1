"""Each error type from a bad scene or argument: InputError with the file, line and key each
bad scene's `# expect:` comment names (tests/scenes/bad), NumericalError with the frames up to
the failure, OutputError and DirectoryBusy from the output folder."""
import fcntl
import re

import pytest

from conftest import FIVEBAR_RIGID, PENDULUM, SOURCE_DIR, files_below

BAD_SCENES = sorted((SOURCE_DIR / "tests" / "scenes" / "bad").glob("*.yaml"))
# Meshing scenes start sandboxed Gmsh children (seconds each; tests/test_bad_scenes.cpp runs them).
QUICK_BAD_SCENES = [p for p in BAD_SCENES if not re.search(r"geo|gmsh|msh|mesh|huge|bomb", p.name)]
EXPECT = re.compile(r"# expect: (?P<file>[^:]+):(?P<line>\d+): key '(?P<key>[^']*)'")


def expectation(path):
    found = EXPECT.search(path.read_text())
    return (path.name, 1, "dimension") if found is None else (found["file"], int(found["line"]), found["key"])


@pytest.mark.parametrize("path", QUICK_BAD_SCENES, ids=lambda p: p.stem)
def test_bad_scene_raises_input_error_naming_file_line_and_key(flexsens_module, path):
    flexsens_module.allow_path(SOURCE_DIR)  # bad scenes share meshes of tests/scenes and examples
    with pytest.raises(flexsens_module.InputError) as caught:
        scene = flexsens_module.load(path)
        scene.counts  # what only `check` and `run` raise (a massless direction nothing holds)
        scene.run(t_end=scene.integrator["t_end"]) if scene.integrator else scene.static()
    error = caught.value
    file, line, key = expectation(path)
    assert error.file == str(path) and error.file.endswith(file)
    assert (error.line, error.key) == (line, key), str(error)
    assert error.message and error.message in str(error)
    assert isinstance(error, flexsens_module.Error)


def test_bad_arguments_raise_input_error_naming_the_keyword(flexsens_module):
    scene = flexsens_module.load(PENDULUM)
    with pytest.raises(flexsens_module.InputError) as caught:
        scene.run(t_end=-1.0)
    assert caught.value.key == "t_end" and caught.value.file is None
    with pytest.raises(flexsens_module.InputError) as caught:
        scene.run(integrator="euler")
    assert caught.value.key == "integrator" and "euler" in caught.value.message
    with pytest.raises(flexsens_module.InputError) as caught:
        scene.run(parameters={"width": 2.0})
    assert caught.value.key == "parameters" and "'width'" in caught.value.message
    assert caught.value.file == str(PENDULUM)
    with pytest.raises(flexsens_module.InputError):
        scene.run(case="no_such_case")
    with pytest.raises(flexsens_module.InputError) as caught:
        flexsens_module.load(FIVEBAR_RIGID).run()  # three cases: which one?
    assert caught.value.key == "cases" and "R1, R2, R3" in caught.value.message
    with pytest.raises(flexsens_module.InputError):
        flexsens_module.load(SOURCE_DIR / "no_such_scene.yaml")


def test_newton_failure_raises_numerical_error_with_the_frames_so_far(flexsens_module):
    # A huge step with one Newton iteration cannot converge (as tests/test_outputs.cpp).
    text = FIVEBAR_RIGID.read_text().replace("  dt: 1.0e-3", "  dt: 0.5\n  max_newton_iterations: 1")
    scene = flexsens_module.loads(text, base_dir=FIVEBAR_RIGID.parent)
    with pytest.raises(flexsens_module.NumericalError) as caught:
        scene.run(case="R1")
    error = caught.value
    assert "Newton did not converge" in str(error) and "t = 0.5 s" in str(error)
    assert error.result.status == "failed" and error.result.reason == str(error)
    assert len(error.result) >= 1 and error.result.t[0] == 0.0


def test_foreign_files_in_the_output_folder_raise_output_error(flexsens_module, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    with pytest.raises(flexsens_module.OutputError) as caught:
        flexsens_module.load(PENDULUM).run(t_end=0.1, out=out)
    assert "notes.txt" in str(caught.value)
    assert files_below(tmp_path) == ["out", "out/notes.txt"]
    assert (out / "notes.txt").read_text() == "mine"


def test_a_locked_output_folder_raises_directory_busy(flexsens_module, tmp_path):
    # Another run holds the folder's lock (output/OutputLock.hpp: <parent>/.<name>.lock).
    with open(tmp_path / ".out.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        with pytest.raises(flexsens_module.DirectoryBusy) as caught:
            flexsens_module.load(PENDULUM).run(t_end=0.1, out=tmp_path / "out")
    assert isinstance(caught.value, flexsens_module.OutputError)
    assert not (tmp_path / "out").exists()
