#!/usr/bin/env python3
"""What a run costs through the Python module against the same run by the CLI (not a test).

For each scene and case, REPEAT times, each in turn first: `flexsens run SCENE --case C --out DIR`
(process wall time, and its integration time: summary.json wall_time_s, the run from the
initial state to the committed folder), Scene.run(case=C, out=DIR) (the call's wall time and
its summary's wall_time_s) and Scene.run(case=C) without files. The minimum over the
repetitions of each is the number kept (other work on the machine only ever adds time); before
each run the files of the previous one are written back (sync), so that no run pays for
another's.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead_bench.py [--repeat 7]
Writes bench/python/results.md.
"""
import argparse
import datetime
import json
import os
import pathlib
import subprocess
import sys
import tempfile
import time

import flexsens

ROOT = pathlib.Path(__file__).resolve().parents[1]
EXE = ROOT / "build" / "flexsens"
# scene, case, VTK frames on: the five-bar (n = 8, 5000 steps, 501 frames: the cost per step and
# per frame shows) with and without its VTK frames, the satellite (n = 495, 500 steps, 101 frames).
SCENES = [("examples/fivebar/flexible.yaml", "F1", True), ("examples/fivebar/flexible.yaml", "F1", False),
          ("examples/satellite/satellite.yaml", "SAT1", True)]


def integration_seconds(folder):
    return json.loads((folder / "summary.json").read_text())["wall_time_s"]


def cli_run(scene, case, out):
    os.sync()  # the previous run's files written back first: each run starts with a clean page cache
    start = time.perf_counter()
    proc = subprocess.run([str(EXE), "run", str(scene), "--case", case, "--out", str(out)],
                          capture_output=True, text=True)
    if proc.returncode not in (0, 5):  # 5: complete but suspect (the satellite's BDF-1 run)
        raise RuntimeError(proc.stderr)
    return time.perf_counter() - start, integration_seconds(out / case)


def python_run(scene, case, out=None):
    os.sync()
    start = time.perf_counter()
    result = scene.run(case=case, out=out)
    return time.perf_counter() - start, result.summary["wall_time_s"]


def scene_file(scene_path, vtk):
    """The scene, or beside it a copy without VTK frames (series.csv and summary.json only)."""
    if vtk:
        return ROOT / scene_path
    text = (ROOT / scene_path).read_text()
    assert "\noutput:\n  directory:" in text
    copy = ROOT / scene_path.replace(".yaml", "_bench_novtk.yaml")  # beside it: its files resolve
    copy.write_text(text.replace("\noutput:\n", "\noutput:\n  vtk: false\n"))
    return copy


def measure(scene_path, case, repeat, work):
    scene = flexsens.load(scene_path)
    times = {"cli": [], "cli_integration": [], "py_files": [], "py_files_integration": [], "py_memory": [],
             "py_memory_integration": []}
    variants = [("cli", lambda i: cli_run(scene_path, case, work / f"cli{i}")),
                ("py_files", lambda i: python_run(scene, case, work / f"py{i}")),
                ("py_memory", lambda i: python_run(scene, case))]
    for i in range(repeat):
        # In turn first, second and third: the run after a CLI process finds the caches cold.
        for name, run in variants[i % 3:] + variants[:i % 3]:
            wall, integration = run(i)
            times[name].append(wall)
            times[name + "_integration"].append(integration)
    return {key: min(values) for key, values in times.items()}


def table(rows, repeat):
    lines = [f"# Runs through Python against the CLI\n",
             f"`bench/python_overhead_bench.py --repeat {repeat}`, {datetime.date.today()}, commit "
             f"{subprocess.run(['git', 'rev-parse', '--short', 'HEAD'], cwd=ROOT, capture_output=True, text=True).stdout.strip()}, "
             "2 shared cores; minimum over the repetitions, each in turn first [s]. Integration: summary.json `wall_time_s` "
             "(initial state to committed folder). Call: the whole `Scene.run` (it reads the scene again, "
             "as the CLI does) or the whole CLI process.\n",
             "| scene, case | CLI process | CLI integration | Python call, out=DIR | its integration | "
             "Python call, no files | its integration | integration Python/CLI (files) | "
             "call no files / CLI integration | call out=DIR / CLI process |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for (scene, case, vtk), t in rows:
        lines.append(f"| {scene} {case}{'' if vtk else ', no VTK frames'} | {t['cli']:.3f} | {t['cli_integration']:.3f} | {t['py_files']:.3f} | "
                     f"{t['py_files_integration']:.3f} | {t['py_memory']:.3f} | {t['py_memory_integration']:.3f} | "
                     f"{t['py_files_integration'] / t['cli_integration']:.3f} | "
                     f"{t['py_memory'] / t['cli_integration']:.3f} | {t['py_files'] / t['cli']:.3f} |")
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for scene, case, vtk in SCENES:
            path = scene_file(scene, vtk)
            try:
                rows.append(((scene, case, vtk), measure(path, case, args.repeat, pathlib.Path(tmp) / f"{case}{vtk}")))
            finally:
                if not vtk:
                    path.unlink()
    text = table(rows, args.repeat)
    out = ROOT / "bench" / "python" / "results.md"
    out.parent.mkdir(exist_ok=True)
    out.write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
