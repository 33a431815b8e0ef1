#!/usr/bin/env bash
# Fixed-step runs of the massless satellite beside the IDAS reference (run.sh): the paper's
# BDF-1 at dt 0.02 s, and the low-dissipation schemes (trapezoidal rule, generalized-alpha at
# rho_inf 0.8, 0.9, 0.95, 0.99 and 1) at dt 1e-3 s, the trapezoidal rule and rho_inf 0.99 and 1
# also at dt 1e-4 s (omega_max dt ~ 1, `flexsens modes`), and the trapezoidal rule with velocity
# and acceleration projections (--projections on) at both steps, generalized-alpha at rho_inf 1 and
# 0.99 with them at dt 1e-3 s, each for a PIM case over 10 s.
#   bash bench/satellite_reference/fixed.sh CASE [RUN ...]   (RUN: a name below; default all)
# Writes runs/CASE_<RUN>/ (series.csv, summary.json, cpu.txt, run.log, commit.txt) like run.sh.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
bin="${FLEXSENS:-$root/build/flexsens}"
case_name="$1"; shift
wanted=" $* "
commit="$(git -C "$root" rev-parse --short HEAD)"  # the checkout at the start (build it first)
mkdir -p "$here/runs"
run() {  # name, then flexsens options
  local name="$1"; shift
  [ "$wanted" = "  " ] || [[ "$wanted" == *" $name "* ]] || return 0
  local out="$here/runs/${case_name}_$name"
  rm -rf "$out"; mkdir -p "$out"
  /usr/bin/time -f "%U %S %e %M" -o "$out/cpu.txt" \
    "$bin" run "$root/examples/satellite/satellite_massless.yaml" --case "$case_name" --t-end 10 \
    --out "$out" "$@" > "$out/run.log" 2>&1 || echo "run $case_name $name ended non-zero: see $out/run.log"
  echo "$commit" > "$out/commit.txt"
  rm -f "$out"/*/frame_*.vtu
}
run bdf1_dt0.02 --integrator bdf1 --dt 0.02
run trapezoidal_dt1e-3 --integrator trapezoidal --dt 1e-3
run ga0.8_dt1e-3 --integrator generalized_alpha --rho-inf 0.8 --dt 1e-3
run ga1_dt1e-3 --integrator generalized_alpha --rho-inf 1 --dt 1e-3
run ga0.9_dt1e-3 --integrator generalized_alpha --rho-inf 0.9 --dt 1e-3
run ga0.95_dt1e-3 --integrator generalized_alpha --rho-inf 0.95 --dt 1e-3
run ga0.99_dt1e-3 --integrator generalized_alpha --rho-inf 0.99 --dt 1e-3
run trapezoidal_dt1e-4 --integrator trapezoidal --dt 1e-4
run ga1_dt1e-4 --integrator generalized_alpha --rho-inf 1 --dt 1e-4
run ga0.99_dt1e-4 --integrator generalized_alpha --rho-inf 0.99 --dt 1e-4
run trapezoidal_proj_dt1e-3 --integrator trapezoidal --dt 1e-3 --projections on
run trapezoidal_proj_dt1e-4 --integrator trapezoidal --dt 1e-4 --projections on
run ga1_proj_dt1e-3 --integrator generalized_alpha --rho-inf 1 --dt 1e-3 --projections on
run ga0.99_proj_dt1e-3 --integrator generalized_alpha --rho-inf 0.99 --dt 1e-3 --projections on
