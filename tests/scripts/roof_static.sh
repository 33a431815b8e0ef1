#!/bin/bash
# The Scordelis-Lo roof as a user writes it (bench/statics/shell_benchmarks.py: Kirchhoff-Love
# triangles, diaphragm ends by `support`, 32 elements along the length) through
# `flexsens static` with `static: {linear: true}`: the free edge's midside sags within 1% of
# the published 0.3024 (MacNeal & Harder 1985). usage: roof_static.sh FLEXSENS SOURCE_DIR
set -euo pipefail
exe=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
read -r scene nodes < <(BENDING=kirchhoff python3 "$src/bench/statics/shell_benchmarks.py" roof 32 "$work")
sed -i 's/static: {load_steps: 1}/static: {linear: true}/' "$scene"
grep -q 'linear: true' "$scene"
"$exe" static "$scene" --out "$work/out" > "$work/log" 2>&1 || { cat "$work/log"; exit 1; }
python3 - "$work/out/summary.json" <<'PY'
import json, sys
js = json.load(open(sys.argv[1]))
assert js["status"] == "complete", js["status"]
sag = 19.151111077974452 - js["final"]["midside_z"]  # the rest height of the midside node
ratio = sag / 0.3024
print("roof N = 32, linear: midside sag %.5f, %.4f of 0.3024" % (sag, ratio))
sys.exit(0 if abs(ratio - 1.0) <= 0.01 else 1)
PY
