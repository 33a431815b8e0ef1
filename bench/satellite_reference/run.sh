#!/usr/bin/env bash
# The converged reference of the massless satellite (issue #14): IDAS over the full 10 s of
# examples/satellite/satellite_massless.yaml at rtol = atol = 1e-6, 1e-8, 1e-10 for a PIM case,
# with the analytic sensitivities (dd), frames every 0.1 s.
#   bash bench/satellite_reference/run.sh CASE RTOL [RTOL ...]   (e.g. SAT1 1e-10 1e-8)
# Each run writes bench/satellite_reference/runs/CASE_rRTOL/ (series.csv, summary.json) and
# its CPU time to .../cpu.txt; runs of one call go one after another (start two calls to use
# two cores). analyze.py compares them. FLEXSENS: the binary (default build/flexsens).
# SENS_ERROR_CONTROL=false: sensitivities out of IDAS' error test (integrator key
# sensitivity_error_control), written to runs/CASE_rRTOL_noserr/.
# SENS_TOLERANCE=state: IDAS' own sensitivity tolerances, estimated from the state's (integrator
# key sensitivity_tolerance; the scene asks for normwise), written to runs/CASE_rRTOL_state/.
# CASE = nominal: the motion alone (the scene without its parameters and cases; needs
# python3-yaml), written to runs/nominal_rRTOL/.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
bin="${FLEXSENS:-$root/build/flexsens}"
case_name="$1"; shift
mkdir -p "$here/runs"
for rtol in "$@"; do
  out="$here/runs/${case_name}_r${rtol}"
  errcon="${SENS_ERROR_CONTROL:-true}"
  [ "$errcon" = true ] || out="${out}_noserr"
  senstol="${SENS_TOLERANCE:-normwise}"
  [ "$senstol" = normwise ] || out="${out}_${senstol}"
  scene="$(mktemp --suffix=.yaml)"
  # rtol = atol (positions in m, velocities in m/s, sensitivities scaled by IDAS from these)
  sed -e "s/^  rtol: .*/  rtol: $rtol/" -e "s/^  atol: .*/  atol: $rtol/" \
      -e "s/^integrator:.*/&\n  sensitivity_error_control: $errcon/" \
      -e "s/^  sensitivity_tolerance: .*/  sensitivity_tolerance: $senstol/" \
      -e "s#gmsh: ../../meshes#gmsh: $root/meshes#" \
      "$root/examples/satellite/satellite_massless.yaml" > "$scene"
  rm -rf "$out"
  commit="$(git -C "$root" rev-parse --short HEAD)"  # the checkout at the start (build it first)
  case_args=(--case "$case_name")
  if [ "$case_name" = nominal ]; then
    python3 -c 'import sys, yaml; d = yaml.safe_load(open(sys.argv[1])); d.pop("parameters", None); d.pop("cases", None); yaml.safe_dump(d, open(sys.argv[1], "w"), sort_keys=False)' "$scene"
    case_args=()
  fi
  /usr/bin/time -f "%U %S %e %M" -o "$out.time" \
    "$bin" run "$scene" --integrator idas "${case_args[@]}" --t-end 10 --out "$out" \
    > "$out.log" 2>&1 || echo "run $case_name rtol $rtol failed: see $out.log"
  mkdir -p "$out"; mv "$out.time" "$out/cpu.txt"; mv "$out.log" "$out/run.log"
  echo "$commit" > "$out/commit.txt"
  rm -f "$out"/*/frame_*.vtu "$out"/frame_*.vtu "$scene"   # keep the series and the summary (frames: 50 MB)
done
