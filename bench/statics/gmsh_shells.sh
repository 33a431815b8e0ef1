#!/bin/bash
# The Scordelis-Lo roof, the pinched cylinder's eighth and the pinched hemisphere's quarter on
# unstructured Gmsh meshes (roof.geo, cylinder_eighth.geo, hemisphere.geo) through `flexsens static` with `linear: true`, bending:
# kirchhoff, membrane ${MEMBRANE:-patch}; element size L / N for N elements along the full
# length (the hemisphere: N along its quarter equator, size (pi R / 2) / N).
# usage: gmsh_shells.sh [WORKDIR] [FLEXSENS]; prints one line per mesh as run.sh does.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
work=${1:-/tmp/flexsens_bench_gmsh_shells}
exe=${2:-$here/../../build/flexsens}
membrane=${MEMBRANE:-patch}
mkdir -p "$work"
cp "$here/roof.geo" "$here/cylinder_eighth.geo" "$here/hemisphere.geo" "$work/"
run() {  # kind N scene output rest reference
  local kind=$1 n=$2 scene=$3 out=$4 rest=$5 ref=$6
  local t0=$(date +%s.%N)
  "$exe" static "$scene" --out "$work/${kind}_$n" > "$work/${kind}_$n.log" 2>&1 || { echo "$kind $n FAILED: $(tail -1 "$work/${kind}_$n.log")"; return; }
  local t1=$(date +%s.%N)
  python3 - "$work/${kind}_$n/summary.json" "$out" "$rest" "$ref" "$kind" "$n" "$t0" "$t1" <<'PY'
import json, sys
js = json.load(open(sys.argv[1]))
d = abs(float(sys.argv[3]) - js["final"][sys.argv[2]])  # the magnitude
ref = float(sys.argv[4])
print("%s N=%s displacement=%.6g reference=%g ratio=%.4f wall=%.1fs" % (
    sys.argv[5], sys.argv[6], d, ref, d / ref, float(sys.argv[8]) - float(sys.argv[7])))
PY
}
for n in ${ROOF_N:-16 32 64}; do
  cat > "$work/roof_gmsh_$n.yaml" <<YAML
# Scordelis-Lo roof, unstructured, size L / $n (bench/statics/gmsh_shells.sh)
dimension: 3
gravity: [0, 0, -10]
elements:
  - {name: shell, type: shell, mesh: roof.geo, group: shell, size: $(python3 -c "print(50 / $n)"), E: 4.32e8, nu: 0.0,
     density: 36, thickness: 0.25, bending: kirchhoff, membrane: $membrane, support: [{group: ends, fix: [y, z]}]}
constraints:
  - {name: axial0, type: prescribed_coordinate, node: midside, axis: x, function: {type: constant, value: 0}}
  - {name: axial1, type: prescribed_coordinate, node: midside2, axis: x, function: {type: constant, value: 0}}
static: {linear: true}
outputs:
  - {name: midside_z, node: midside, component: z}
YAML
  run roof_gmsh "$n" "$work/roof_gmsh_$n.yaml" midside_z 19.151111077974452 0.3024
done
for n in ${CYL_N:-32 64 128}; do
  cat > "$work/eighth_gmsh_$n.yaml" <<YAML
# Pinched cylinder, an eighth, unstructured, size L / $n (bench/statics/gmsh_shells.sh)
dimension: 3
elements:
  - {name: shell, type: shell, mesh: cylinder_eighth.geo, group: shell, size: $(python3 -c "print(600 / $n)"), E: 3.0e6,
     nu: 0.3, density: 1, thickness: 3.0, bending: kirchhoff, membrane: $membrane, support: [{group: ends, fix: [y, z]}],
     symmetry: [{group: mid, normal: x}, {group: crown, normal: y}, {group: side, normal: z}]}
  - {name: P_top, type: point_force, node: top, force: [0, 0, -0.25]}
static: {linear: true}
outputs:
  - {name: top_z, node: top, component: z}
YAML
  run eighth_gmsh "$n" "$work/eighth_gmsh_$n.yaml" top_z 300 1.8248e-5
done
for n in ${HEMI_N:-}; do
  cat > "$work/hemisphere_gmsh_$n.yaml" <<YAML
# Pinched hemisphere, a quarter, unstructured, N = $n along the quarter equator (bench/statics/gmsh_shells.sh)
dimension: 3
elements:
  - {name: shell, type: shell, mesh: hemisphere.geo, group: shell, size: $(python3 -c "import math; print(5 * math.pi / $n)"),
     E: 6.825e7, nu: 0.3, density: 1, thickness: 0.04, bending: kirchhoff, membrane: $membrane,
     symmetry: [{group: px, normal: x}, {group: py, normal: y}]}
  - {name: FA, type: point_force, node: A, force: [1, 0, 0]}
  - {name: FB, type: point_force, node: B, force: [0, -1, 0]}
constraints:
  - {name: zfix, type: prescribed_coordinate, node: C, axis: z, function: {type: constant, value: 0}}
static: {linear: true}
outputs:
  - {name: A_x, node: A, component: x}
YAML
  run hemisphere_gmsh "$n" "$work/hemisphere_gmsh_$n.yaml" A_x 10 0.094
done
