#!/bin/bash
# Mesh series of Cook's membrane (bench/statics/cook.yaml) with linear and quadratic triangles:
# one line per mesh with the vertical displacement of the right edge's midpoint C against 23.96,
# and of the top right corner.
# usage: cook.sh [WORKDIR] [FLEXSENS]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
work=${1:-/tmp/flexsens_bench_cook}
exe=${2:-$here/../../build/flexsens}
mkdir -p "$work"
cp "$here/cook.geo" "$work/"
for order in 1 2; do
  for size in ${SIZES:-8 4 2 1}; do
    sed -e "s/size: 2, order: 2/size: $size, order: $order/" "$here/cook.yaml" > "$work/cook_${order}_$size.yaml"
    "$exe" static "$work/cook_${order}_$size.yaml" --out "$work/cook_${order}_$size" > /dev/null 2>&1 || { echo "order $order size $size FAILED"; continue; }
    python3 - "$work/cook_${order}_$size/summary.json" "$order" "$size" <<'PY'
import json, sys
js = json.load(open(sys.argv[1]))
v = js["final"]["C_uy"]
print("order %s size %s n=%d C_uy=%.5f ratio=%.4f dC_uy/dE=%.5f dC_uy/dnu=%.5f corner_uy=%.5f" % (
    sys.argv[2], sys.argv[3], js["n"], v, v / 23.96, js["final"]["dC_uy/dE"], js["final"]["dC_uy/dnu"],
    js["final"]["corner_uy"]))
PY
  done
done
