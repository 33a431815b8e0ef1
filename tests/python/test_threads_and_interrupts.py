"""Runs release the GIL: two threads run two scenes at once with the results of running them
one after the other, and Python goes on while a run computes. Ctrl-C (SIGINT) during a run
raises KeyboardInterrupt and stops it cleanly at the end of a step (its folder says
`interrupted`); so does an exception from the progress callback."""
import json
import os
import signal
import threading

import numpy as np
import pytest

from conftest import FIVEBAR_FLEXIBLE, FIVEBAR_RIGID, PENDULUM


def test_two_threads_run_two_scenes_with_the_serial_results(flexsens_module):
    jobs = {"pendulum": (flexsens_module.load(PENDULUM), {"t_end": 1.0}),
            "fivebar": (flexsens_module.load(FIVEBAR_RIGID), {"case": "R2", "t_end": 1.0})}
    serial = {name: scene.run(**options) for name, (scene, options) in jobs.items()}
    parallel, errors = {}, []

    def run(name):
        try:
            scene, options = jobs[name]
            parallel[name] = scene.run(**options)
        except Exception as e:  # reported below: an exception in a thread would pass silently
            errors.append(e)

    threads = [threading.Thread(target=run, args=(name,)) for name in jobs]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    for name in jobs:
        np.testing.assert_array_equal(parallel[name].q, serial[name].q)
        np.testing.assert_array_equal(parallel[name].dq, serial[name].dq)
        assert parallel[name].status == serial[name].status == "complete"


def test_python_runs_while_a_run_computes(flexsens_module):
    # The run's first progress call wakes the main thread. Had the run kept the GIL, the main
    # thread could only go on once the whole run had ended.
    scene = flexsens_module.load(FIVEBAR_FLEXIBLE)
    started, finished = threading.Event(), threading.Event()

    def run():
        scene.run(case="F1", t_end=2.0, progress=lambda t, t_end: started.set())
        finished.set()

    worker = threading.Thread(target=run)
    worker.start()
    assert started.wait(timeout=120)
    ran_during_the_run = not finished.is_set()
    worker.join()
    assert ran_during_the_run


def test_progress_reports_time_up_to_t_end(flexsens_module):
    calls = []
    flexsens_module.load(PENDULUM).run(t_end=0.5, progress=lambda t, t_end: calls.append((t, t_end)))
    assert calls, "no progress call"
    assert all(t_end == 0.5 and 0.0 <= t <= t_end for t, t_end in calls)
    assert abs(calls[-1][0] - 0.5) < 1e-9  # the last call says where the run ended


def summary_of(folder):
    return json.loads((folder / "summary.json").read_text())


def test_sigint_raises_keyboard_interrupt_and_stops_the_run_cleanly(flexsens_module, tmp_path):
    scene = flexsens_module.load(FIVEBAR_FLEXIBLE)
    first_progress = threading.Event()
    # SIGINT from another thread once the run is under way, as Ctrl-C in a terminal.
    sender = threading.Thread(target=lambda: first_progress.wait(120) and os.kill(os.getpid(), signal.SIGINT))
    sender.start()
    with pytest.raises(KeyboardInterrupt):
        scene.run(case="F1", out=tmp_path, progress=lambda t, t_end: first_progress.set())
    sender.join()
    summary = summary_of(tmp_path / "F1")
    assert summary["status"] == "interrupted"
    assert 0.0 < summary["t_reached"] < 5.0
    # The next run is not stopped by the old request.
    assert scene.run(case="F1", t_end=0.05).status == "complete"


def test_an_exception_in_the_progress_callback_stops_the_run(flexsens_module, tmp_path):
    def fail(t, t_end):
        raise ValueError(f"stop at {t}")

    with pytest.raises(ValueError, match="stop at"):
        flexsens_module.load(FIVEBAR_FLEXIBLE).run(case="F1", out=tmp_path, progress=fail)
    assert summary_of(tmp_path / "F1")["status"] == "interrupted"
