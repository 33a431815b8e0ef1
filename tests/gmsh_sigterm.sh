#!/bin/bash
# SIGTERM to flexsens while its Gmsh child evaluates an endless loop in a scene's .geo:
#   run   (interrupt handler installed): kills the child, exits 143 within 2 s, writes nothing;
#   check (SIGTERM's default action):    the child dies with its parent (PR_SET_PDEATHSIG).
# The CPU limit is raised to 60 s so that only the signal can end the loop.
#   bash tests/gmsh_sigterm.sh <flexsens executable>
set -u
EXE=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
SRC=$(cd "$(dirname "$0")/.." && pwd)
W=$(mktemp -d)
trap 'rm -rf "$W"' EXIT
cp "$SRC"/tests/scenes/bad/hostile/panel.geo "$SRC"/tests/scenes/bad/hostile/endless_loop.geo "$W"/
cat > "$W"/scene.yaml <<'YAML'
dimension: 3
limits: {gmsh_cpu_s: 60}
elements:
  - {name: panel, type: shell, mesh: endless_loop.geo, group: panel, size: 0.05,
     E: 4.0e9, nu: 0.38, density: 1380, thickness: 0.0005, ground: [hinge]}
integrator: {type: trapezoidal, t_end: 0.004, dt: 0.001}
YAML
fail() { echo "FAIL: $*"; exit 1; }
alive() { local s; s=$(awk '/^State:/ {print $2}' /proc/$1/status 2>/dev/null); [ -n "$s" ] && [ "$s" != Z ]; }

for cmd in run check; do
  args=("$cmd" scene.yaml)
  [ "$cmd" = run ] && args+=(--out "$W/out")
  (cd "$W" && exec "$EXE" "${args[@]}") > "$W/$cmd.out" 2> "$W/$cmd.err" &
  pid=$!
  child=""
  for _ in $(seq 1 100); do  # up to 10 s for scene reading to reach Gmsh
    child=$(pgrep -P $pid | head -1)
    [ -n "$child" ] && break
    sleep 0.1
  done
  [ -n "$child" ] || fail "$cmd: no Gmsh child process appeared; stderr: $(cat "$W/$cmd.err")"
  sleep 0.5  # well inside the loop
  kill -TERM $pid
  for _ in $(seq 1 20); do alive $pid || break; sleep 0.1; done
  if alive $pid; then kill -KILL $pid; fail "$cmd: still running 2 s after SIGTERM"; fi
  wait $pid
  rc=$?
  [ $rc = 143 ] || fail "$cmd: exit status $rc, expected 143 (128 + SIGTERM); stderr: $(cat "$W/$cmd.err")"
  for _ in $(seq 1 20); do alive "$child" || break; sleep 0.1; done
  if alive "$child"; then kill -KILL "$child"; fail "$cmd: the Gmsh child outlived flexsens by 2 s"; fi
done
grep -q "interrupted by SIGTERM while Gmsh read '.*endless_loop.geo'; nothing written" "$W/run.err" ||
  fail "run: stderr should say it was interrupted inside Gmsh: $(cat "$W/run.err")"
[ -e "$W/out" ] && fail "run created its output folder"
echo "OK: run and check end within 2 s of SIGTERM inside Gmsh, the child with them"
