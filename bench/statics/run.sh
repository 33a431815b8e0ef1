#!/bin/bash
# Mesh series of the Scordelis-Lo roof and the pinched cylinder through `flexsens static`
# (bench/statics/results.md). usage: run.sh [WORKDIR] [FLEXSENS]; prints one line per mesh:
# benchmark, N, nodes, displacement, reference, ratio, wall time. Variables: MODES (nonlinear
# linear), ROOF_N, CYL_N, EIGHTH_N (mesh lists), BENDING, MEMBRANE (shell_benchmarks.py).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
work=${1:-/tmp/flexsens_bench_statics}
exe=${2:-$here/../../build/flexsens}
mkdir -p "$work"
run() {  # kind N output rest reference [linear]
  local kind=$1 n=$2 out=$3 rest=$4 ref=$5 mode=${6:-}
  read -r scene nodes < <(python3 "$here/shell_benchmarks.py" "$kind" "$n" "$work")
  if [ "$mode" = linear ]; then
    sed 's/static: {load_steps: 1}/static: {linear: true}/' "$scene" > "${scene%.yaml}_linear.yaml"
    scene=${scene%.yaml}_linear.yaml
    kind=${kind}_linear
  fi
  local t0=$(date +%s.%N)
  "$exe" static "$scene" --out "$work/${kind}_$n" > "$work/${kind}_$n.log" 2>&1 || { echo "$kind $n $nodes FAILED: $(tail -1 "$work/${kind}_$n.log")"; return; }
  local t1=$(date +%s.%N)
  python3 - "$work/${kind}_$n/summary.json" "$out" "$rest" "$ref" "$kind" "$n" "$nodes" "$t0" "$t1" <<'PY'
import json, sys
js = json.load(open(sys.argv[1]))
z = js["final"][sys.argv[2]]
d = float(sys.argv[3]) - z
ref = float(sys.argv[4])
print("%s N=%s nodes=%s iterations=%d displacement=%.6g reference=%g ratio=%.4f wall=%.1fs" % (
    sys.argv[5], sys.argv[6], sys.argv[7], js["statistics"]["newton_iterations"], d, ref, d / ref,
    float(sys.argv[9]) - float(sys.argv[8])))
PY
}
for mode in ${MODES:-nonlinear linear}; do
  for n in ${ROOF_N:-8 16 32 64 96}; do run roof "$n" midside_z 19.151111077974452 0.3024 "$mode"; done
  for n in ${CYL_N:-8 16 32 48 64}; do run cylinder "$n" top_z 300 1.8248e-5 "$mode"; done
  for n in ${EIGHTH_N:-}; do run eighth "$n" top_z 300 1.8248e-5 "$mode"; done
done
