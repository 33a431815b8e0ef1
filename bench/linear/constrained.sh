#!/usr/bin/env bash
# Solvers for the Newton matrices of constrained continua (issue #41; not a test): dumps the
# first Newton matrix (FLEXSENS_DUMP_MATRIX, core/SparseLU.cpp) of meshed bodies held by
# constraint rows at growing n, and of the multibody models beside them, and runs
# `bench_linear_compare --constrained` (bench/linear/constrained.cpp) on each. Writes
# bench/linear/constrained.md.
#   bash bench/linear/constrained.sh [build-dir] [--quick]
set -euo pipefail
cd "$(dirname "$0")/../.."
B=${1:-build}
QUICK=${2:-}
cmake --build "$B" --target flexsens bench_linear_compare >/dev/null
W=$(mktemp -d)
trap 'rm -rf "$W"' EXIT
OUT=bench/linear/constrained.md
cp bench/linear/pendulum_root.geo examples/shell/panel.geo examples/fivebar/meshed_link.geo "$W/"

pendulum() {  # size holding: the bar (examples/solid/pendulum3d.yaml) held by `holding`
  cat <<YAML
dimension: 3
gravity: [0, -9.81, 0]
nodes:
  - {name: A, position: [0, 0.02, -0.05], ground: true}
  - {name: B, position: [0, 0.02, 0.05], ground: true}
  - {name: C, position: [-0.05, 0.02, 0]}
  - {name: D, position: [0, 0.07, 0]}
elements:
  - {name: hub, type: rigid_body, nodes: [A, B, C, D], mass: 0.2, center_of_mass: [-0.02, 0.03, 0], inertia: [1e-4, 1e-4, 1e-4]}
  - {name: bar, type: solid, mesh: pendulum_root.geo, group: bar, size: $1, order: 2, material: neo_hookean,
     E: 2.0e6, nu: 0.3, density: 1000, $2}
integrator: {type: trapezoidal, t_end: 0.005, dt: 0.005}
output: {vtk: false}
YAML
}

panel() {  # size: the shell panel (examples/shell/panel.yaml) held on its hinge edge by support rows
  cat <<YAML
dimension: 3
gravity: [0, 0, -9.81]
elements:
  - {name: panel, type: shell, mesh: panel.geo, group: panel, size: $1,
     E: 4.0e9, nu: 0.38, density: 1380, thickness: 0.0005, support: [{group: hinge, fix: [x, y, z]}]}
integrator: {type: trapezoidal, t_end: 0.001, dt: 0.001}
output: {vtk: false}
YAML
}

table() {  # title name scene at [run options...]: dumps factorization `at` and compares
  local title=$1 name=$2 scene=$3 at=$4; shift 4
  FLEXSENS_DUMP_MATRIX="$W/$name" FLEXSENS_DUMP_AT=$at "$B/flexsens" run "$scene" --out "$W/out_$name" "$@" \
    >/dev/null 2>&1 || true  # exit 5 (suspect) is fine: only the matrices are wanted
  echo "## $title"
  echo
  "$B/bench_linear_compare" --constrained "$W/${name}_$at.mtx"
  echo
}

if [ -n "$QUICK" ]; then SOLID=(0.04); SHELL=(0.0065); else SOLID=(0.04 0.014 0.0105); SHELL=(0.0065 0.0025 0.0017); fi
{
  echo "# Solvers on the Newton matrices of constrained continua"
  echo
  echo "\`bash bench/linear/constrained.sh\` ($(date -u +%F), $(nproc) cores, OpenBLAS serial). Each table: the"
  echo "first Newton matrix [M/(beta h^2) + K, Phi_q^T; Phi_q, 0] of a trapezoidal run (dt 5 ms, 1 ms"
  echo "for the shell and the five-bar), every solver on the same matrix (bench/linear/constrained.cpp):"
  echo "fill = entries of the factors / nnz(A) (a symmetric factor's L counted twice, its diagonal"
  echo "once), factor = best of 3 (KLU: its refactorization), solve = one right-hand side,"
  echo "backward error = max_i |b - A x|_i / (|A||x| + |b|)_i of one plain solve with b = 1."
  echo
  for s in "${SOLID[@]}"; do
    pendulum "$s" "support: [{group: hinge, fix: [x, y, z]}]" > "$W/sup$s.yaml"
    table "Solid pendulum held by support rows on its hinge edge, size $s m" "sup$s" "$W/sup$s.yaml" 0
    pendulum "$s" "attach: [{group: root, body: hub}]" > "$W/att$s.yaml"
    table "Solid pendulum, end face welded (attach) to a hinged rigid body, size $s m" "att$s" "$W/att$s.yaml" 0
  done
  for s in "${SHELL[@]}"; do
    panel "$s" > "$W/panel$s.yaml"
    table "Shell panel held by support rows on its hinge edge, size $s m" "panel$s" "$W/panel$s.yaml" 0
  done
  cp examples/fivebar/meshed_link.yaml "$W/fivebar.yaml"
  table "Five-bar with a meshed link (planar triangles), case F1, 2nd factorization" fivebar "$W/fivebar.yaml" 1 --case F1 --t-end 0.3
  table "Five-bar with the meshed link modelled rigid (F1R twin), 2nd factorization" fivebarR "$W/fivebar.yaml" 1 --case F1R --t-end 0.3
  python3 - "$W/sat.yaml" <<'PY'
import sys; sys.path.insert(0, "bench")
import satellite_bench as sb
open(sys.argv[1], "w").write(sb.variant(10, 0, 1.0))
PY
  table "Satellite refine 10 (multibody, BDF-1), 1st factorization" sat "$W/sat.yaml" 0 --allow-path "$PWD/examples/satellite"
} > "$OUT"
echo "wrote $OUT"
