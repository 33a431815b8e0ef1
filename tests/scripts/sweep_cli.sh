#!/bin/bash
# `flexsens sweep` through the command line, one process (issue 38): grid, Latin-hypercube,
# case and static sweeps (counts, order, a sample's numbers against its own `flexsens run` of
# the scene with the value written into it), failing and hanging samples kept with their
# reason while the sweep goes on, bad options, the output folder's safety, Ctrl-C.
# One part per ctest entry (each well under 30 s):
#   bash tests/scripts/sweep_cli.sh <build>/flexsens <checkout> grid|lhs|cases|perturbed|static|failures|errors|output|interrupt
set -u
. "$(dirname "$0")/sweep_lib.sh"

part_grid() {
  echo "== grid: 3 x 2 values, outputs at two times"
  sweep "$OSC" --parameter k=40:60:3 --parameter c=0.2:0.4:2 --at 0.25 --at 0.5 --out g --no-plots
  expect "exit 0 (got $rc)" '[ $rc = 0 ]'
  expect "6 rows" '[ "$(rows "$W/g/sweep.csv")" = 6 ]'
  expect "rows in sample order, the first parameter slowest" \
    '[ "$(for i in 0 1 2 3 4 5; do printf "%s/%s/%s " $(cell "$W/g/sweep.csv" $i index) $(cell "$W/g/sweep.csv" $i k) $(cell "$W/g/sweep.csv" $i c); done)" = "0/40/0.2 1/40/0.4 2/50/0.2 3/50/0.4 4/60/0.2 5/60/0.4 " ]'
  expect "every sample complete" '[ "$(grep -c ",complete,," "$W/g/sweep.csv")" = 6 ]'
  expect "value and sensitivity columns per time" \
    'head -1 "$W/g/sweep.csv" | grep -q "tip_x@0.25,dtip_x/dm@0.25,dtip_x/dk@0.25,dtip_x/dc@0.25,tip_y@0.25" && head -1 "$W/g/sweep.csv" | grep -q "dtip_y/dc@0.5$"'
  echo "== sample 3 (k = 50, c = 0.4) against its own run of the scene with damping: 0.4 written in"
  sed 's/damping: 0.5}/damping: 0.4}/' "$OSC" > "$W/osc_c04.yaml"
  (cd "$W" && "$FLEXSENS" run osc_c04.yaml --out own > /dev/null 2>&1); rc=$?
  expect "its own run exits 0 (got $rc)" '[ $rc = 0 ]'
  expect "outputs and sensitivities at both times equal, digit for digit" \
    'same_as_run "$W/g/sweep.csv" 3 "$W/own/series.csv"'
  expect "no scratch folder left" 'no_scratch_left'
}

part_lhs() {
  echo "== Latin hypercube: 8 samples over k and m, seed 5"
  sweep "$OSC" --parameter k=30:70 --parameter m=0.5:1.5 --samples 8 --seed 5 --out h1 --no-plots
  expect "exit 0 (got $rc)" '[ $rc = 0 ]'
  expect "8 rows, all complete" '[ "$(rows "$W/h1/sweep.csv")" = 8 ] && [ "$(grep -c ",complete,," "$W/h1/sweep.csv")" = 8 ]'
  expect "each of the 8 strata of k and of m holds one sample" \
    'python3 -c "
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for p, lo, hi in ((\"k\", 30, 70), (\"m\", 0.5, 1.5)):
    s = sorted(int((float(r[p]) - lo) / (hi - lo) * 8) for r in rows)
    assert s == list(range(8)), (p, s)
" "$W/h1/sweep.csv"'
  expect "sweep.json: latin_hypercube, seed 5" \
    'grep -q "\"design\": \"latin_hypercube\"" "$W/h1/sweep.json" && grep -q "\"seed\": 5," "$W/h1/sweep.json"'
  sweep "$OSC" --parameter k=30:70 --parameter m=0.5:1.5 --samples 8 --seed 5 --out h2 --no-plots
  expect "the same seed: the same table" 'cmp -s "$W/h1/sweep.csv" "$W/h2/sweep.csv"'
  sweep "$OSC" --parameter k=30:70 --parameter m=0.5:1.5 --samples 8 --seed 6 --out h3 --no-plots
  expect "another seed: other samples" '! cmp -s "$W/h1/sweep.csv" "$W/h3/sweep.csv"'
}

part_cases() {
  echo "== two PIM cases of the flexible five-bar at two natural lengths of spring B-1"
  sweep "$FB" --cases F2,F5 --parameter L_B1=2.2:2.26:2 --t-end 0.3 --out c --no-plots
  expect "exit 0 (got $rc)" '[ $rc = 0 ]'
  expect "4 rows: each length with F2 then F5" \
    '[ "$(for i in 0 1 2 3; do printf "%s/%s " $(cell "$W/c/sweep.csv" $i L_B1) $(cell "$W/c/sweep.csv" $i case); done)" = "2.2/F2 2.2/F5 2.26/F2 2.26/F5 " ]'
  expect "F2's sensitivity is to L_A1, F5's to L_B1 (the other empty)" \
    '[ -n "$(cell "$W/c/sweep.csv" 2 dz2/dL_A1@0.3)" ] && [ -z "$(cell "$W/c/sweep.csv" 2 dz2/dL_B1@0.3)" ] && [ -z "$(cell "$W/c/sweep.csv" 3 dz2/dL_A1@0.3)" ] && [ -n "$(cell "$W/c/sweep.csv" 3 dz2/dL_B1@0.3)" ]'
  echo "== sample 3 (L_B1 = 2.26, F5) against its own run with natural_length: 2.26 written in"
  sed 's/nodes: \[B, n1\], stiffness: 1000, damping: 0}/nodes: [B, n1], stiffness: 1000, damping: 0, natural_length: 2.26}/' "$FB" > "$W/fb.yaml"
  (cd "$W" && "$FLEXSENS" run fb.yaml --case F5 --t-end 0.3 --out own > /dev/null 2>&1); rc=$?
  expect "its own run exits 0 (got $rc)" '[ $rc = 0 ]'
  expect "z2 and dz2/dL_B1 equal, digit for digit" 'same_as_run "$W/c/sweep.csv" 3 "$W/own/F5/series.csv"'
}

part_perturbed() {
  echo "== --start perturbed: case F1 of the five-bar over L_A1 = sqrt(2) -+ 1e-4 (F1 rigidizes what L_A1 moves)"
  local low=1.4141135623730951 high=1.4143135623730951
  sweep "$FB" --case F1 --parameter L_A1=$low:$high:3 --t-end 0.3 --out sc --no-plots
  expect "from the scene's positions (default): the two off-nominal samples fail naming the deformed body" \
    '[ $rc = 5 ] && [ "$(cell "$W/sc/sweep.csv" 0 status)" = failed ] && grep -q "not undeformed" "$W/sc/sweep.csv"'
  sweep "$FB" --case F1 --parameter L_A1=$low:$high:3 --t-end 0.3 --start perturbed --out pe --no-plots
  expect "from the perturbed start: exit 0 (got $rc), every sample complete" \
    '[ $rc = 0 ] && [ "$(grep -c ",complete,," "$W/pe/sweep.csv")" = 3 ]'
  expect "the middle sample's dz2/dL_A1 equals the central difference of the outer two runs to 1e-6" \
    'python3 -c "
import csv, sys
r = list(csv.DictReader(open(sys.argv[1])))
fd = (float(r[2][\"z2@0.3\"]) - float(r[0][\"z2@0.3\"])) / (float(r[2][\"L_A1\"]) - float(r[0][\"L_A1\"]))
exact = float(r[1][\"dz2/dL_A1@0.3\"])
assert abs(fd - exact) <= 1e-6 * abs(exact), (fd, exact)
" "$W/pe/sweep.csv"'
}

part_static() {
  echo "== static sweep: equilibrium per stiffness"
  sweep "$OSC" --static --parameter k=40:60:3 --out s --no-plots
  expect "exit 0 (got $rc), 3 rows" '[ $rc = 0 ] && [ "$(rows "$W/s/sweep.csv")" = 3 ]'
  sed 's/stiffness: 50,/stiffness: 60,/' "$OSC" > "$W/osc_k60.yaml"
  (cd "$W" && "$FLEXSENS" static osc_k60.yaml --out own > /dev/null 2>&1)
  expect "sample 2 (k = 60) equals its own flexsens static at load factor 1" \
    'python3 -c "
import csv, sys
row = list(csv.DictReader(open(sys.argv[1])))[2]
last = list(csv.DictReader(open(sys.argv[2])))[-1]
cols = [c for c in row if c.startswith((\"tip\", \"dtip\"))]
assert cols and all(row[c] == last[c] for c in cols), [(c, row[c], last[c]) for c in cols]
" "$W/s/sweep.csv" "$W/own/series.csv"'
}

part_failures() {
  echo "== a sample that fails (m = 0: the tip has no mass but a damper) does not stop the sweep"
  sweep "$OSC" --parameter m=0:1:3 --out f --no-plots
  expect "exit 5: the table is written, not every sample complete (got $rc)" '[ $rc = 5 ]'
  expect "sample 0 failed with the run's reason" \
    '[ "$(cell "$W/f/sweep.csv" 0 status)" = failed ] && cell "$W/f/sweep.csv" 0 reason | grep -q massless'
  expect "samples 1 and 2 complete, with values" \
    '[ "$(cell "$W/f/sweep.csv" 1 status)" = complete ] && [ "$(cell "$W/f/sweep.csv" 2 status)" = complete ] && [ -n "$(cell "$W/f/sweep.csv" 2 tip_x@0.5)" ]'
  expect "the report names the failed sample" 'grep -q "failed: sample 0: " "$W/out"'
  expect "sweep.json lists it" 'grep -q "\"failed\": \[0\]" "$W/f/sweep.json"'
  echo "== suspect samples (BDF-1 at dt = 10 ms damps the pendulum) keep their values and the audit's reason"
  sweep "$SRC/examples/pendulum/pendulum.yaml" --parameter m=1:2:2 --integrator bdf1 --dt 0.01 --out u --no-plots
  expect "exit 5 (got $rc)" '[ $rc = 5 ]'
  expect "both suspect, the energy audit's reason, values kept" \
    '[ "$(cell "$W/u/sweep.csv" 1 status)" = suspect ] && cell "$W/u/sweep.csv" 1 reason | grep -q "energy audit" && [ -n "$(cell "$W/u/sweep.csv" 1 tip_x@2)" ]'
  echo "== a sample past --sample-time-limit (IDAS at k = 1e12) is killed and lost"
  sweep "$OSC" --parameter k=50:1e12:2 --integrator idas --sample-time-limit 2 --out t --no-plots
  expect "exit 5 (got $rc)" '[ $rc = 5 ]'
  expect "sample 1 lost at the time limit, sample 0 complete" \
    '[ "$(cell "$W/t/sweep.csv" 1 status)" = lost ] && cell "$W/t/sweep.csv" 1 reason | grep -q "time limit of 2 s.*--sample-time-limit" && [ "$(cell "$W/t/sweep.csv" 0 status)" = complete ]'
  echo "== a sample whose process is killed (kill -9) is lost, the sweep goes on"
  (cd "$W" && exec "$FLEXSENS" sweep "$OSC" --parameter k=40:60:3 --t-end 2 --dt 2e-5 --out x --no-plots > "$W/out" 2> "$W/err") &
  BG=$!
  local child=""
  for _ in $(seq 300); do child=$(pgrep -P $BG); [ -n "$child" ] && break; sleep 0.05; done
  sleep 0.3; kill -9 $child; wait $BG; rc=$?; BG=""
  expect "exit 5 (got $rc)" '[ $rc = 5 ]'
  expect "sample 0 lost, killed by signal 9, samples 1 and 2 complete" \
    '[ "$(cell "$W/x/sweep.csv" 0 status)" = lost ] && cell "$W/x/sweep.csv" 0 reason | grep -q "killed by signal 9" && [ "$(cell "$W/x/sweep.csv" 2 status)" = complete ]'
  expect "no scratch folder left" 'no_scratch_left'
}

part_errors() {
  echo "== bad options: exit 1 naming the option, nothing written"
  mkdir -p "$W/e"
  local cases=(
    "--parameter|--parameter L=1:2:3|no parameter 'L'"
    "--parameter|--parameter k=a:2:3|not a finite number"
    "--parameter|--parameter k=1:2:x|COUNT must be a whole number"
    "--parameter|--parameter m=-1:1:3|must not be negative"
    "--parameter|--parameter k=1:2:3 --parameter m=0.5:1|one or the other"
    "--samples|--parameter k=1:2|--samples"
    "--at|--parameter k=1:2:3 --at 0.123|not a frame time"
    "--output|--parameter k=1:2:3 --output nope|no output 'nope'"
    "--at|--parameter k=1:2:3 --static --at 0.5|static sweep"
    "--start|--parameter k=1:2:3 --static --start perturbed|static sweep finds each equilibrium"
  )
  for c in "${cases[@]}"; do
    IFS='|' read -r option args message <<< "$c"
    (cd "$W/e" && eval "\"$FLEXSENS\" sweep \"$OSC\" $args --out out" > "$W/out" 2> "$W/err"); rc=$?
    expect "$args: exit 1 (got $rc), names $option: $message" \
      '[ $rc = 1 ] && grep -q -- "option $option" "$W/err" && grep -q -- "$message" "$W/err"'
  done
  sed '/^outputs:/,/^output:/{/^output:/!d}' "$OSC" > "$W/no_outputs.yaml"  # the outputs list removed
  (cd "$W/e" && "$FLEXSENS" sweep ../no_outputs.yaml --parameter k=1:2:3 --out out > "$W/out" 2> "$W/err"); rc=$?
  expect "a scene without outputs: exit 1 (got $rc), names --output" '[ $rc = 1 ] && grep -q "option --output: .* has no outputs" "$W/err"'
  expect "nothing written" '[ -z "$(ls -A "$W/e")" ] && no_scratch_left'
}

part_output() {
  echo "== the output folder: user files refused (4), a busy folder refused (6), reruns replace"
  mkdir -p "$W/user"; echo "my notes" > "$W/user/notes.txt"
  sweep "$OSC" --parameter k=40:60:2 --out user --no-plots
  expect "a folder with user files: exit 4 (got $rc), kept" '[ $rc = 4 ] && [ "$(cat "$W/user/notes.txt")" = "my notes" ] && said "flexsens did not write"'
  (cd "$W" && flock -n .busy.lock "$FLEXSENS" sweep "$OSC" --parameter k=40:60:2 --out busy > "$W/out" 2> "$W/err"); rc=$?
  expect "a locked folder: exit 6 (got $rc)" '[ $rc = 6 ] && said "another flexsens run"'
  sweep "$OSC" --parameter k=40:60:2 --out kept --keep-samples --no-plots
  expect "--keep-samples: samples/<index>/ with series.csv and summary.json (rc $rc)" \
    '[ $rc = 0 ] && [ -f "$W/kept/samples/1/series.csv" ] && [ -f "$W/kept/samples/1/summary.json" ] && grep -q "^dir samples$" "$W/kept/.flexsens-manifest"'
  expect "a kept sample is its own run: sample 1's row equals its series.csv" \
    'same_as_run "$W/kept/sweep.csv" 1 "$W/kept/samples/1/series.csv"'
  sweep "$OSC" --parameter k=40:60:3 --out kept --no-plots
  expect "a rerun replaces the earlier sweep, samples/ with it (rc $rc)" \
    '[ $rc = 0 ] && [ "$(rows "$W/kept/sweep.csv")" = 3 ] && [ ! -e "$W/kept/samples" ]'
  if /usr/bin/python3 -c "import matplotlib" 2> /dev/null; then
    sweep "$OSC" --parameter k=40:60:3 --out p
    expect "sweep.png drawn (rc $rc) and kept by the manifest" \
      '[ $rc = 0 ] && [ -s "$W/p/sweep.png" ] && grep -q "^keep sweep.png$" "$W/p/.flexsens-manifest"'
    sweep "$OSC" --parameter k=40:60:3 --parameter c=0.2:0.4:3 --out p
    expect "a two-parameter sweep redraws it (rc $rc)" '[ $rc = 0 ] && [ -s "$W/p/sweep.png" ]'
  else
    echo "skip: no matplotlib for /usr/bin/python3: sweep.png not checked"
  fi
}

part_interrupt() {
  echo "== Ctrl-C: the sweep stops, the table keeps what finished"
  (cd "$W" && exec "$FLEXSENS" sweep "$FB" --case F5 --parameter L_B1=2.18:2.29:40 --out i --no-plots > "$W/out" 2> "$W/err") &
  BG=$!
  for _ in $(seq 300); do  # until two samples have finished; a guard, not a timing check
    [ "$(grep -c " complete " "$W/err" 2> /dev/null || true)" -ge 2 ] 2> /dev/null && break
    sleep 0.1
  done
  local child; child=$(pgrep -P $BG)  # the running sample's process
  kill -INT $BG; wait $BG; rc=$?; BG=""
  expect "exit 130 (got $rc)" '[ $rc = 130 ]'
  expect "sweep.json says interrupted by SIGINT" \
    'grep -q "\"status\": \"interrupted\"" "$W/i/sweep.json" && grep -q "\"interrupted_by\": \"SIGINT\"" "$W/i/sweep.json"'
  expect "40 rows: the finished ones complete, the others interrupted or not_run" \
    'python3 -c "
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
st = [r[\"status\"] for r in rows]
assert len(rows) == 40 and st.count(\"complete\") >= 2 and set(st) <= {\"complete\", \"interrupted\", \"not_run\"}, st
" "$W/i/sweep.csv"'
  expect "no sample process left (${child:-none running})" '! { [ -n "$child" ] && kill -0 $child 2> /dev/null; } && no_scratch_left'
}

"part_$3"
finish "sweep_cli $3"
