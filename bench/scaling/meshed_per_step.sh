#!/usr/bin/env bash
# Per-step cost per coordinate of the meshed bodies at n ~ 1.7k and n ~ 25k (issue 41's
# measure): the solid pendulum at element sizes 0.04 and 0.01 m, the shell panel (no cases) at
# 0.0065 and 0.0017 m, 10 steps, no parameters, the scenes of run.py; each run twice,
# alternated. Prints the counters of summary.json and wall_time_s / steps / n.
#   bench/scaling/meshed_per_step.sh [build/flexsens]
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
F="$(realpath "${1:-$ROOT/build/flexsens}")"
W="$(mktemp -d)"
trap 'rm -rf "$W"' EXIT
cp "$ROOT/examples/solid/pendulum3d.geo" "$ROOT/examples/shell/panel.geo" "$W/"
/usr/bin/python3 - "$ROOT/bench/scaling/run.py" "$W" <<'PY'
import importlib.util, os, sys
path, work = sys.argv[1], sys.argv[2]
spec = importlib.util.spec_from_file_location("run", path)
run = importlib.util.module_from_spec(spec)
sys.argv = [path]
spec.loader.exec_module(run)
for size in (0.04, 0.01):
    open(os.path.join(work, "solid_%g.yaml" % size), "w").write(run.solid_scene(size, 0))
for size in (0.0065, 0.0017):
    open(os.path.join(work, "panel_%g.yaml" % size), "w").write(run.panel_scene(size, 0))
PY
cd "$W"
for round in 1 2; do
  for f in solid_0.04 solid_0.01 panel_0.0065 panel_0.0017; do
    "$F" run $f.yaml --out "o_$f" > /dev/null 2>&1
    /usr/bin/python3 - "o_$f/summary.json" "$round" "$f" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
st = s["statistics"]
def find(d, k):
    if isinstance(d, dict):
        for a, b in d.items():
            if a == k:
                return b
            r = find(b, k)
            if r is not None:
                return r
n, w = find(s, "n"), s["wall_time_s"]
print("| %s | %s | %d | %d | %d | %.3f | %.3f | %.2f | %.2f |" % (sys.argv[2], sys.argv[3], n, st["factorizations"],
      st["newton_iterations"], st["factorization_seconds"], w, 1e6 * w / st["steps"] / n, st["lu_fill"]))
PY
    rm -rf "o_$f"
  done
done
