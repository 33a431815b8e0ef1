# Shared by tests/scripts/sweep_cli.sh and sweep_mpi.sh: the scratch folder, checks and the
# readers of sweep.csv and series.csv (sourced; $1 the flexsens executable, $2 the checkout).
FLEXSENS=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
SRC=$(cd "$2" && pwd)
OSC=$SRC/tests/scenes/sweep/oscillator.yaml
FB=$SRC/examples/fivebar/flexible.yaml
W=$(mktemp -d)
W=$(cd "$W" && pwd -P)
export TMPDIR=$W/tmp  # the samples' scratch folders: checked to be gone at the end
mkdir -p "$TMPDIR"
BG=""
cleanup() { [ -n "$BG" ] && kill -9 "$BG" 2>/dev/null; rm -rf "$W"; }
trap cleanup EXIT
fails=0
ok() { echo "ok:   $1"; }
bad() { echo "FAIL: $1"; fails=$((fails + 1)); }
expect() { if eval "$2"; then ok "$1"; else bad "$1 [$2]"; fi; }
# sweep ARGS...: `flexsens sweep ARGS` in $W, stdout/stderr in $W/out, $W/err; sets rc
sweep() { (cd "$W" && "$FLEXSENS" sweep "$@" > "$W/out" 2> "$W/err"); rc=$?; }
said() { grep -q -- "$1" "$W/err" "$W/out"; }
# cell CSV ROW COLUMN: the cell of sweep.csv's data row ROW (0 first) under header COLUMN
cell() {
  python3 - "$@" <<'EOF'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print(rows[int(sys.argv[2])][sys.argv[3]])
EOF
}
# rows CSV: the number of data rows
rows() { python3 -c "import csv,sys; print(len(list(csv.DictReader(open(sys.argv[1])))))" "$1"; }
# same_as_run SWEEP_CSV ROW SERIES_CSV: every value column of the sweep row equals the
# series.csv cell of the same output at the column's time, as text (0 when all do)
same_as_run() {
  python3 - "$@" <<'EOF'
import csv, sys
row = list(csv.DictReader(open(sys.argv[1])))[int(sys.argv[2])]
series = list(csv.DictReader(open(sys.argv[3])))
checked = 0
for column, value in row.items():
    if "@" not in column:
        continue
    name, t = column.rsplit("@", 1)
    at = [r for r in series if abs(float(r[next(iter(r))]) - float(t)) < 1e-9]
    if value == "" and len(at) == 1 and name not in at[0]:
        continue  # a sensitivity to a parameter of another case: not in this run
    if len(at) != 1 or at[0].get(name) != value:
        print("differs:", column, value, at[0].get(name) if at else "(no row at t)")
        sys.exit(1)
    checked += 1
print(checked, "columns equal")
sys.exit(0 if checked else 1)
EOF
}
no_scratch_left() { [ -z "$(ls -A "$TMPDIR")" ]; }
finish() {
  echo
  [ $fails = 0 ] && echo "$1: all checks passed" || echo "$1: $fails checks FAILED"
  [ $fails = 0 ]
}
