#!/bin/bash
# flexsens deletes or replaces only what it wrote, one run per output folder (issue 34): the
# reproducers out_dot_deletes_project.sh, out_paths.sh and concurrent_cases_lost.sh with their
# outcomes reversed. Short runs (--t-end 0.02) in a scratch folder.
#   bash tests/scripts/out_safety.sh <build>/flexsens <checkout>
set -u
FLEXSENS=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
SRC=$(cd "$2" && pwd)
SC=$SRC/examples/seed000/double_pendulum.yaml
W=$(mktemp -d)
W=$(cd "$W" && pwd -P)
BG=""
cleanup() { [ -n "$BG" ] && kill -9 "$BG" 2>/dev/null; rm -rf "$W"; }
trap cleanup EXIT
fails=0
ok() { echo "ok:   $1"; }
bad() { echo "FAIL: $1"; fails=$((fails + 1)); }
expect() { if eval "$2"; then ok "$1"; else bad "$1 [$2]"; fi; }
# run DIR ARGS...: `flexsens ARGS` in DIR, stdout/stderr in $W/out, $W/err; sets rc
run() { local d=$1; shift; (cd "$d" && "$FLEXSENS" "$@" > "$W/out" 2> "$W/err"); rc=$?; }
said() { grep -q -- "$1" "$W/err"; }

echo "== A: --out . in a project folder holding an earlier run in a subfolder"
mkdir -p "$W/proj/src"
cp "$SC" "$W/proj/scene.yaml"
echo "three years of work" > "$W/proj/thesis.tex"; echo "int main(){}" > "$W/proj/src/main.c"
run "$W/proj" run scene.yaml --t-end 0.02 --out run1
expect "first run into ./run1 exits 0" '[ $rc = 0 ]'
run "$W/proj" run scene.yaml --t-end 0.02 --out .
expect "--out . is refused with exit 4 (got $rc)" '[ $rc = 4 ]'
expect "the message names the user's files" 'said "flexsens did not write" && said thesis.tex && said "src/"'
expect "thesis.tex, scene.yaml, src/main.c kept" \
  '[ "$(cat "$W/proj/thesis.tex")" = "three years of work" ] && [ -f "$W/proj/scene.yaml" ] && [ -f "$W/proj/src/main.c" ]'
expect "the earlier run in run1/ kept" '[ -f "$W/proj/run1/summary.json" ]'
expect "nothing added to the project folder" '[ "$(ls -A "$W/proj" | tr "\n" " ")" = ".run1.lock run1 scene.yaml src thesis.tex " ]'

echo "== B: a folder of user files that holds a file named series.csv"
mkdir -p "$W/data/photos"; echo "t,x" > "$W/data/series.csv"; echo precious > "$W/data/notes.txt"; echo jpg > "$W/data/photos/a.jpg"
run "$W" run "$SC" --t-end 0.02 --out "$W/data"
expect "refused with exit 4 (got $rc)" '[ $rc = 4 ] && said "flexsens did not write"'
expect "notes.txt, photos/a.jpg and the user's series.csv kept" \
  '[ "$(cat "$W/data/notes.txt")" = precious ] && [ -f "$W/data/photos/a.jpg" ] && [ "$(cat "$W/data/series.csv")" = "t,x" ]'

echo "== C: --out ~ with an earlier run in ~/sim1"
mkdir -p "$W/home/Documents"; echo letter > "$W/home/Documents/letter.txt"; echo "export X=1" > "$W/home/.profile"
(export HOME="$W/home"; cd "$HOME" && "$FLEXSENS" run "$SC" --t-end 0.02 --out ~/sim1 > /dev/null 2>&1); rc=$?
expect "run into ~/sim1 exits 0" '[ $rc = 0 ]'
(export HOME="$W/home"; cd "$HOME" && "$FLEXSENS" run "$SC" --t-end 0.02 --out ~ > "$W/out" 2> "$W/err"); rc=$?
expect "--out ~ is refused with exit 4 (got $rc)" '[ $rc = 4 ] && said "flexsens did not write"'
expect "Documents/, .profile and sim1/ kept" \
  '[ -f "$W/home/Documents/letter.txt" ] && [ -f "$W/home/.profile" ] && [ -f "$W/home/sim1/summary.json" ]'

echo "== D: a scene with output: {directory: ..} run from a subfolder"
mkdir -p "$W/victim/work"; echo important > "$W/victim/important.txt"
run "$W" run "$SC" --t-end 0.02 --out "$W/victim/results_old"
sed 's#directory: results/double_pendulum#directory: ..#' "$SC" > "$W/victim/work/scene.yaml"
run "$W/victim/work" run scene.yaml --t-end 0.02
expect "refused with exit 4 (got $rc)" '[ $rc = 4 ] && said "flexsens did not write"'
expect "important.txt, results_old/, work/scene.yaml kept" \
  '[ -f "$W/victim/important.txt" ] && [ -f "$W/victim/results_old/summary.json" ] && [ -f "$W/victim/work/scene.yaml" ]'

echo "== E: --out through a symbolic link, and a/../b"
mkdir -p "$W/p/bigdisk"
run "$W/p" run "$SC" --t-end 0.01 --out bigdisk/results
ln -s bigdisk/results "$W/p/link1"
run "$W/p" run "$SC" --t-end 0.02 --out link1
expect "run through the link exits 0 (got $rc)" '[ $rc = 0 ]'
expect "link1 is still a symbolic link" '[ -L "$W/p/link1" ]'
expect "the link's target holds the new run" 'grep -q "\"t_reached\": 0.02" "$W/p/bigdisk/results/summary.json"'
mkdir -p "$W/p/deep/inner"; ln -s deep/inner "$W/p/a"
run "$W/p" run "$SC" --t-end 0.02 --out a/../b
expect "a/../b is written where the kernel resolves it, deep/b (rc $rc)" '[ $rc = 0 ] && [ -f "$W/p/deep/b/summary.json" ] && [ ! -e "$W/p/b" ]'

echo "== F: one lock per resolved folder, for every kind of run (held here with flock(1))"
mkdir -p "$W/l/real"; ln -s real "$W/l/link2"
(cd "$W/l" && flock -n .real.lock "$FLEXSENS" run "$SC" --t-end 0.02 --out link2 > "$W/out" 2> "$W/err"); rc=$?
expect "run through a link to a locked folder: exit 6 (got $rc)" '[ $rc = 6 ] && said "another flexsens run is writing $W/l/real"'
expect "link2 is still a symbolic link" '[ -L "$W/l/link2" ]'
(cd "$W/l" && flock -n .D.lock "$FLEXSENS" run "$SRC/examples/shell/panel.yaml" --t-end 0.002 --out D > "$W/out" 2> "$W/err"); rc=$?
expect "PIM cases into a locked folder: exit 6 (got $rc)" '[ $rc = 6 ] && said "another flexsens run"'
(cd "$W/l" && flock -n .D.lock "$FLEXSENS" run "$SC" --t-end 0.02 --out D/F1 > "$W/out" 2> "$W/err"); rc=$?
expect "a run into a subfolder of a locked folder: exit 6 (got $rc)" '[ $rc = 6 ] && said "which holds $W/l/D/F1"'
(cd "$W/l" && flock -n .S.lock "$FLEXSENS" study --quick --out S --source "$SRC" > "$W/out" 2> "$W/err"); rc=$?
expect "study into a locked folder: exit 6 at once (got $rc)" '[ $rc = 6 ] && said "another flexsens run"'
(cd "$W/l" && flock -n .T.lock "$FLEXSENS" static "$SRC/examples/ancf/beam3d_shaft.yaml" --out T > "$W/out" 2> "$W/err"); rc=$?
expect "static into a locked folder: exit 6 (got $rc)" '[ $rc = 6 ] && said "another flexsens run"'
expect "nothing written by the refused runs" '[ ! -e "$W/l/D" ] && [ ! -e "$W/l/S" ] && [ ! -e "$W/l/T" ] && [ -z "$(ls -A "$W/l/real")" ]'

echo "== G: a plain run and a run of PIM cases into one folder at once (concurrent_cases_lost.sh)"
mkdir -p "$W/c"
(cd "$W/c" && exec "$FLEXSENS" run "$SC" --t-end 500 --out D > "$W/a.out" 2> "$W/a.err") & BG=$!
for _ in $(seq 3000); do  # until A holds the lock (its staging folder exists); a guard, not a timing check
  compgen -G "$W/c/.D.staging-*" > /dev/null && break
  kill -0 $BG 2> /dev/null || break
  sleep 0.1
done
run "$W/c" run "$SRC/examples/shell/panel.yaml" --t-end 0.002 --out D
expect "the second run (cases) refuses with exit 6 (got $rc)" '[ $rc = 6 ] && said "another flexsens run is writing $W/c/D"'
expect "it does not claim results" '! grep -q "results written" "$W/out"'
kill -TERM $BG; wait $BG; rca=$?; BG=""
expect "the first run ends interrupted (143, got $rca) with its results in D" \
  '[ $rca = 143 ] && grep -q "\"status\": \"interrupted\"" "$W/c/D/summary.json"'
run "$W/c" run "$SRC/examples/shell/panel.yaml" --t-end 0.002 --out D
expect "the cases run afterwards replaces the earlier run: exit 0 (got $rc), D/F1 and D/R" \
  '[ $rc = 0 ] && [ -f "$W/c/D/F1/summary.json" ] && [ -f "$W/c/D/R/summary.json" ] && [ ! -e "$W/c/D/series.csv" ]'
run "$W/c" run "$SRC/examples/shell/panel.yaml" --t-end 0.002 --case F1 --out D
expect "--case F1 replaces F1 and keeps R (rc $rc)" '[ $rc = 0 ] && [ -f "$W/c/D/R/summary.json" ]'

echo
[ $fails = 0 ] && echo "out_safety: all checks passed" || echo "out_safety: $fails checks FAILED"
[ $fails = 0 ]
