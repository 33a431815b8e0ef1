#!/usr/bin/env python3
"""Scene fuzzer: mutates every example and test scene (fixed seed) and runs flexsens on each
mutant. A crash (signal), a hang (time limit), exit 3 (other error) on bad input, an exit-1
message without `file:line:col: key '...'`, or a NaN/Inf in the outputs of a run that said
it succeeded is a failure. Exit status 1 when there is any failure, 0 otherwise.

    python3 scripts/fuzz_scenes.py --exe build/flexsens --count 200      # CTest's short form
    bash bench/fuzz_long.sh                                             # 3000 mutations

Mutations: structural (a value anywhere in the tree replaced by an extreme or ill-typed
value, keys deleted, renamed or repeated, list items dropped or duplicated, numbers scaled)
on the parsed scene, and textual (lines deleted or duplicated, characters flipped, the file
cut short, lists and mappings used as keys) on its text; and, every tenth mutant, a hostile
command put into a copy of a meshed body's or geometry's .geo (SystemCall, Printf > file,
Include of /dev/zero or of a file outside the scene's folder, Save, Exit, Sleep, an endless
loop, an 80 GB list, meshing at 1e-5 m): it must end in a located error (exit 1) and leave no
marker file. Base scenes are shortened to a few steps first so that runs stay fast; `gmsh:`
and `mesh:` paths are made absolute (mutants live elsewhere), so meshed bodies are meshed.
A run that exits 0 must leave every number of every CSV, summary.json and ASCII VTU finite,
and summary.json's status must say `complete` (exit 5: `suspect`).
"""
import argparse
import concurrent.futures
import glob
import json
import math
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# The key may itself hold a quote (a mutated `nod'`): the location is what must be there.
LOCATED = re.compile(r"flexsens: error: (.*):([0-9]+):([0-9]+): key '.*': \S")
SPECIAL = [0, -1, 1, 1e308, -1e308, 1e-308, 5e-324, float("nan"), float("inf"), 2147483647,
           -2147483648, 9223372036854775807, 1e6, 1e-19, "x", "", "auto", [], {}, [1, 2, 3],
           {"a": 1}, True, None, "/dev/zero", "../../../../etc/passwd"]


def base_scenes():
    files = sorted(glob.glob(os.path.join(ROOT, "examples", "**", "*.yaml"), recursive=True))
    files += sorted(glob.glob(os.path.join(ROOT, "tests", "scenes", "**", "*.yaml"), recursive=True))
    scenes = []
    for f in files:
        text = open(f).read()
        # Geometry and mesh paths relative to the scene: absolute, since mutants live elsewhere.
        text = re.sub(r"(\bgmsh:\s*|\bmesh:\s*)([^\s,}#]+)",
                      lambda m: m.group(1) + os.path.normpath(os.path.join(os.path.dirname(f), m.group(2))), text)
        try:
            data = yaml.safe_load(text)
        except yaml.YAMLError:
            data = None
        # A meshed body's PIM cases make `check` slow (examples/fivebar/meshed_link.yaml: ~1 min
        # of CPU), which would read as a hang; the body is fuzzed without them.
        if isinstance(data, dict) and "cases" in data and re.search(r"\bmesh:", text):
            del data["cases"]
            text = yaml.safe_dump(data, sort_keys=False)
        if isinstance(data, dict) and isinstance(data.get("integrator"), dict):
            integ = data["integrator"]
            dt = integ.get("dt")
            # A few steps are enough to exercise reading, building, the PIM and the writers.
            if isinstance(dt, (int, float)) and dt > 0:
                integ["t_end"] = 4 * dt
                integ.pop("frame_interval", None)
            elif integ.get("type") == "idas":
                integ["t_end"] = 1e-3
                integ["frame_interval"] = 5e-4
            text = yaml.safe_dump(data, sort_keys=False)
        scenes.append((os.path.relpath(f, ROOT), text, data))
    return scenes


# Hostile .geo commands (with the scene's `limits` that keep the test short) for the tenth
# mutants: each must be refused (exit 1, located) and write no marker file.
GEO_ATTACKS = [
    ('SystemCall "touch {marker}";', None),
    ('System "touch {marker}";', None),
    ('Printf("x") > "{marker}";', None),
    ('Printf("%g", 1) >> "{marker}";', None),
    ('Include "/dev/zero";', None),
    ('Include "/etc/hostname";', None),
    ('Include StrCat("/dev/", "zero");', None),
    ('Save "{marker}.msh";', None),
    ('Exit;', None),
    ('Sleep 100;', None),
    ('For fz In {{1:1e15}}\n  gz = fz;\nEndFor', {"gmsh_cpu_s": 1}),
    ('fz[] = {{1:1e10}};', {"gmsh_cpu_s": 2, "gmsh_memory_mb": 256}),
    ('Mesh.MeshSizeMax = 1e-5;\nMesh 2;', {"gmsh_cpu_s": 1, "gmsh_memory_mb": 256}),
]
# Attacks that act on the geometry already defined: at the top of a file they mesh nothing and
# the scene's own size then wins, a harmless file; they go at its end.
AFTER_GEOMETRY = {"Mesh 2;"}
GEO_KEY = re.compile(r"(\b(?:gmsh|mesh):\s*)(/[^\s,}#]+\.geo)\b")


def geo_mutant(rng, scenes, work):
    """A scene whose .geo (copied into `work` as attack.geo) holds a hostile command."""
    name, text, data = rng.choice(scenes)
    m = GEO_KEY.search(text)
    cmd, limits = rng.choice(GEO_ATTACKS)
    lines = open(m.group(2)).read().split("\n")
    at = rng.choice([0, len(lines)])
    if any(a in cmd for a in AFTER_GEOMETRY):
        at = len(lines)
    lines.insert(at, cmd.format(marker=os.path.join(work, "marker_geo")))
    mtext = text[: m.start(2)] + "attack.geo" + text[m.end(2):]
    if limits:
        mtext = "limits: " + json.dumps(limits) + "\n" + mtext
    return name, mtext, {"attack.geo": "\n".join(lines)}


def paths(node, prefix=()):
    """Every (path, value) in the tree."""
    yield prefix, node
    if isinstance(node, dict):
        for k, v in node.items():
            yield from paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from paths(v, prefix + (i,))


def parent_of(data, path):
    for p in path[:-1]:
        data = data[p]
    return data


def mutate_tree(rng, data):
    data = yaml.safe_load(yaml.safe_dump(data))  # deep copy
    candidates = [p for p, _ in paths(data) if p]
    if not candidates:
        return yaml.safe_dump(data)
    for _ in range(rng.choice([1, 1, 1, 2, 3])):
        candidates = [p for p, _ in paths(data) if p]
        if not candidates:
            break
        path = rng.choice(candidates)
        par, key = parent_of(data, path), path[-1]
        op = rng.random()
        if op < 0.5:
            par[key] = rng.choice(SPECIAL)
        elif op < 0.6 and isinstance(par[key], (int, float)) and not isinstance(par[key], bool):
            par[key] = par[key] * rng.choice([-1, 0, 1e-9, 1e9, 1 + 1e-12])
        elif op < 0.7:
            del par[key]
        elif op < 0.8 and isinstance(par, dict):
            par[str(key) + rng.choice(["_", "s", "X"])] = par.pop(key)
        elif op < 0.9 and isinstance(par, list):
            par.insert(key, par[key])
        elif isinstance(par, list) and len(par) > 1:
            j = rng.randrange(len(par))
            par[key], par[j] = par[j], par[key]
        else:
            par[key] = rng.choice(SPECIAL)
    return yaml.safe_dump(data, sort_keys=False, allow_unicode=True)


def mutate_text(rng, text):
    lines = text.split("\n")
    op = rng.random()
    i = rng.randrange(len(lines))
    if op < 0.2:
        del lines[i]
    elif op < 0.35:
        lines.insert(i, lines[i])
    elif op < 0.5:
        lines.insert(i, rng.choice(["[a, b]: 1", "? {x: 1}\n: 2", "{a: 1}: 2", "? [n1]\n: 3"]))
    elif op < 0.6:
        # a list used as a key inside a mapping that the reader walks
        lines.insert(i, re.match(r"\s*", lines[i]).group(0) + "[k]: 1")
    elif op < 0.75:
        s = lines[i]
        if s:
            j = rng.randrange(len(s))
            s = s[:j] + rng.choice(list("[]{}:,-#&*!|>'\"%@` \t0.eE")) + s[j + 1:]
        lines[i] = s
    elif op < 0.85:
        return text[: rng.randrange(len(text) + 1)]
    else:
        lines[i] = re.sub(r"-?\d+(\.\d+)?([eE][-+]?\d+)?", lambda m: rng.choice(
            ["1e308", "-0", "1e-320", "NaN", ".nan", "99999999999999999999", "0x10", "1_000"]), lines[i], count=1)
    return "\n".join(lines)


def short_integrator(mtext, base):
    """A mutant that is also run gets its base scene's short integrator back: a mutated
    t_end of 1e6 s is a valid, long run, not a hang (check still sees every mutated key)."""
    if not isinstance(base, dict) or "integrator" not in base:
        return mtext
    try:
        data = yaml.safe_load(mtext)
    except (yaml.YAMLError, TypeError, ValueError):
        return mtext
    if not isinstance(data, dict):
        return mtext
    data["integrator"] = base["integrator"]
    return yaml.safe_dump(data, sort_keys=False, allow_unicode=True)


def run(cmd, limit, cwd=None):
    try:
        p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=limit, cwd=cwd)
        return p.returncode, p.stderr.decode(errors="replace")
    except subprocess.TimeoutExpired:
        return "hang", ""


def not_finite(x):
    try:
        return not math.isfinite(float(x))
    except ValueError:
        return False  # a text column (a name, a status)


def json_numbers(node):
    if isinstance(node, dict):
        for v in node.values():
            yield from json_numbers(v)
    elif isinstance(node, list):
        for v in node:
            yield from json_numbers(v)
    elif isinstance(node, float):
        yield node


def outputs_bad(out, code):
    """Why the outputs of a run that exited `code` (0 or 5) are wrong, or None."""
    for f in glob.glob(os.path.join(out, "**", "*.csv"), recursive=True):
        for n, line in enumerate(open(f, errors="replace").read().split("\n")[1:], 2):
            if any(not_finite(x) for x in line.split(",") if x.strip()):
                return f"{f}:{n}: a NaN or Inf: {line[:200]}"
    summaries = glob.glob(os.path.join(out, "**", "summary.json"), recursive=True)
    if not summaries:
        return f"{out}: no summary.json"
    want = "complete" if code == 0 else "suspect"
    for f in summaries:
        try:  # json.loads takes NaN and Infinity; they are found below
            data = json.load(open(f))
        except ValueError as e:
            return f"{f}: not JSON: {e}"
        if any(not math.isfinite(x) for x in json_numbers(data)):
            return f"{f}: a NaN or Inf"
        if isinstance(data, dict) and data.get("status") != want:
            return f"{f}: status {data.get('status')!r} after exit {code}; expected {want!r}"
    for f in glob.glob(os.path.join(out, "**", "*.vtu"), recursive=True):
        text = open(f, errors="replace").read()
        for arr in re.findall(r'<DataArray[^>]*format="ascii"[^>]*>([^<]*)<', text):
            if any(not_finite(x) for x in arr.split()):
                return f"{f}: a NaN or Inf in an ASCII DataArray"
    return None


def judge(exe, path, limit, do_run, work):
    """Outcome tag and, for failures, the reason."""
    # Mutants live outside the checkout and name its meshes by absolute path: allow that tree.
    allow = ["--allow-path", ROOT]
    code, err = run([exe, "check", path] + allow, limit, cwd=work)
    tags = []
    for mode in (["check", "run"] if do_run else ["check"]):
        if mode == "run":
            if code != 0:
                break  # run of an invalid scene repeats check's verdict
            out = os.path.join(work, "out")
            code, err = run([exe, "run", path, "--out", out] + allow, limit, cwd=work)
        if code == "hang":
            return f"{mode}:hang", f"over {limit} s"
        if code < 0:
            return f"{mode}:crash", f"signal {-code}\n{err[-2000:]}"
        if code == 3:
            return f"{mode}:exit3", err[-2000:]
        if code == 1 and not any(LOCATED.match(l) and os.path.basename(path) in l for l in err.splitlines()):
            return f"{mode}:unlocated", err[-2000:]
        # exit 5: the run finished but its energy audit marks it suspect (a mutant with a huge
        # step, say): an honest verdict, not a failure of the program.
        if code not in (0, 1, 2) and not (mode == "run" and code == 5):
            return f"{mode}:exit{code}", err[-2000:]
        if mode == "run" and code in (0, 5):
            bad = outputs_bad(os.path.join(work, "out"), code)
            if bad:
                return "run:output", bad
        tags.append(f"{mode}:exit{code}")
    return tags[-1], ""


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "flexsens"))
    ap.add_argument("--count", type=int, default=200)
    ap.add_argument("--seed", type=int, default=13)
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--time-limit", type=float, default=30.0, help="per process [s]; longer is a hang")
    ap.add_argument("--run-fraction", type=float, default=0.25, help="share of valid mutants also run")
    ap.add_argument("--keep", help="directory for the failing mutants")
    args = ap.parse_args()
    args.exe = os.path.abspath(args.exe)  # flexsens runs in each mutant's folder

    rng = random.Random(args.seed)
    scenes = base_scenes()
    root = tempfile.mkdtemp(prefix="flexsens_fuzz_")
    # Valid scenes with a .geo behind `mesh:` or `geometry.gmsh:` (examples, test scenes).
    geo_scenes = [sc for sc in scenes if GEO_KEY.search(sc[1]) and "/bad/" not in sc[0]]
    mutants = []
    # Half the mutants from the valid examples (whose mutants reach the model builder, the PIM
    # and the integrators), half from the test scenes, each list in turn.
    examples = [sc for sc in scenes if sc[0].startswith("examples")]
    others = [sc for sc in scenes if not sc[0].startswith("examples")] or examples
    for i in range(args.count):
        if i % 10 == 9 and geo_scenes:
            name, mtext, files = geo_mutant(rng, geo_scenes, os.path.join(root, f"m{i:05d}"))
            mutants.append((i, name, mtext, False, files))
            continue
        pool_ = examples if i % 2 == 0 else others
        name, text, data = pool_[(i // 2) % len(pool_)]
        if data is not None and rng.random() < 0.6:
            mtext = mutate_tree(rng, data)
        else:
            mtext = mutate_text(rng, text)
        do_run = rng.random() < args.run_fraction
        if do_run:
            mtext = short_integrator(mtext, data)
        mutants.append((i, name, mtext, do_run, {}))

    counts, failures = {}, []

    def one(m):
        i, name, text, do_run, files = m
        work = os.path.join(root, f"m{i:05d}")
        os.makedirs(work)
        path = os.path.join(work, f"mutant_{i:05d}.yaml")
        with open(path, "w") as f:
            f.write(text)
        for fname, content in files.items():
            with open(os.path.join(work, fname), "w") as f:
                f.write(content)
        tag, why = judge(args.exe, path, args.time_limit, do_run, work)
        if files:
            markers = [f for f in os.listdir(work) if f.startswith("marker")]
            if markers:
                tag, why = "geo:escaped", f"the .geo command wrote {markers}"
            elif tag != "check:exit1" and not why:
                tag, why = "geo:accepted", f"a hostile .geo command ended in {tag}, not a located refusal"
            else:
                tag = "geo:" + tag
        return i, name, text, tag, why, work

    try:
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            for i, name, text, tag, why, work in pool.map(one, mutants):
                counts[tag] = counts.get(tag, 0) + 1
                if why:
                    failures.append((i, name, tag, why, text))
                shutil.rmtree(work, ignore_errors=True)
    finally:
        shutil.rmtree(root, ignore_errors=True)

    print(f"fuzz_scenes: {args.count} mutants of {len(scenes)} scenes, seed {args.seed}")
    for tag in sorted(counts):
        print(f"  {tag:16s} {counts[tag]}")
    print(f"  failures         {len(failures)}")
    for i, name, tag, why, text in failures[:20]:
        print(f"--- mutant {i} of {name}: {tag}\n{why.strip()}")
    if args.keep and failures:
        os.makedirs(args.keep, exist_ok=True)
        for i, name, tag, why, text in failures:
            with open(os.path.join(args.keep, f"mutant_{i:05d}.yaml"), "w") as f:
                f.write(f"# {name}: {tag}\n" + text)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
