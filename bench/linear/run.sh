#!/usr/bin/env bash
# Sparse direct solvers on the matrices flexsens factorizes (issue #11; not a test).
# Dumps real Newton matrices (FLEXSENS_DUMP_MATRIX, core/SparseLU.cpp) from the satellite
# refined 1, 2, 5, 10 (BDF-1), the flexible five-bar and the seed-000 four-bar (trapezoidal),
# and runs bench/linear/compare.cpp on each: fill, analysis and factorization times,
# backward error. Writes bench/linear/results.md.
#   bash bench/linear/run.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/../.."
B=${1:-build}
cmake --build "$B" --target flexsens bench_linear_compare >/dev/null
W=$(mktemp -d)
trap 'rm -rf "$W"' EXIT
OUT=bench/linear/results.md

dump() {  # name scene first-factorization [run options...]
  local name=$1 scene=$2 at=$3; shift 3
  FLEXSENS_DUMP_MATRIX="$W/$name" FLEXSENS_DUMP_AT=$at "$B/flexsens" run "$scene" --out "$W/out_$name" "$@" \
    >/dev/null 2>&1 || true  # exit 5 (suspect) is fine: only the matrices are wanted
  python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['n'])" "$W/out_$name/summary.json" 2>/dev/null ||
    python3 -c "import json,glob,sys; print(json.load(open(glob.glob(sys.argv[1] + '/*/summary.json')[0]))['n'])" "$W/out_$name"
}

{
  echo "# Sparse LU on flexsens' Newton matrices"
  echo
  echo "\`bash bench/linear/run.sh\` ($(date -u +%F), $(nproc) cores). Each table: one Newton matrix"
  echo "[M/(beta h^2) + K, Phi_q^T; Phi_q, 0] written during a real run (the 200th factorization"
  echo "unless said), every solver on the same matrix; fill = nnz(L+U)/nnz(A) (the diagonal counted"
  echo "once), factor = one numeric factorization with a fresh pivot search (best of 5), refactor ="
  echo "the same pattern and pivots again (what the integrators do every Newton iteration),"
  echo "residual = |Ax - b|_inf / (|A||x| + |b|)_inf for b = 1, rcond = 1/condest (KLU) or"
  echo "UMFPACK's estimate. KLU's 'predicted' is its symbolic estimate (AMD only)."
  echo
  for r in 1 2 5 10; do
    python3 - "$r" "$W/sat_r$r.yaml" <<'PY'
import sys; sys.path.insert(0, "bench")
import satellite_bench as sb
open(sys.argv[2], "w").write(sb.variant(int(sys.argv[1]), 0, 1.0))
PY
    n=$(dump "sat$r" "$W/sat_r$r.yaml" 200)
    echo "## Satellite, refine $r (BDF-1, dt 0.02 s)"
    echo
    "$B/bench_linear_compare" "$n" "$W/sat${r}_200.mtx"
    echo
  done
  n=$(dump fivebar examples/fivebar/flexible.yaml 200 --case F1 --t-end 0.3)
  echo "## Flexible five-bar F1 (trapezoidal, dt 1e-3 s)"
  echo
  "$B/bench_linear_compare" "$n" "$W/fivebar_200.mtx"
  echo
  n=$(dump fourbar examples/seed000/four_bar.yaml 200 --t-end 0.3)
  echo "## Seed-000 four-bar (trapezoidal, dt 1e-3 s)"
  echo
  "$B/bench_linear_compare" "$n" "$W/fourbar_200.mtx"
  echo
  n=$(dump meshed examples/fivebar/meshed_link.yaml 200 --case F1 --t-end 0.3)
  echo "## Five-bar with link 1-2 a meshed plate (planar triangles, trapezoidal)"
  echo
  "$B/bench_linear_compare" "$n" "$W/meshed_200.mtx"
} > "$OUT"
echo "wrote $OUT"
