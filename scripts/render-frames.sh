#!/usr/bin/env bash
# Renders a flexsens VTK series (RUN_DIR/frames.pvd) to PNG frames with ParaView's pvbatch,
# headless (under Xvfb), coloured by |dq/d<PARAM>|. See scripts/PARAVIEW.md.
#
#   render-frames.sh RUN_DIR OUT_DIR [PARAM] [--every N] [--size WxH] [--no-tube] [--warp S] [--view X,Y,Z]
#   render-frames.sh --check      # exit 0 if ParaView is installed (scripts/install-paraview.sh)
#   render-frames.sh --selftest   # exit 0 if pvbatch starts and renders headless
#
# pvbatch comes from the private prefix written by scripts/install-paraview.sh (default
# /opt/flexsens-paraview, or $FLEXSENS_PARAVIEW_PREFIX), never from /usr/bin.
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
PREFIX="${FLEXSENS_PARAVIEW_PREFIX:-/opt/flexsens-paraview}"
PVBATCH="$PREFIX/usr/bin/pvbatch"
PVLIB="$PREFIX/usr/lib/x86_64-linux-gnu"
PVPY="$PREFIX/usr/lib/python3/dist-packages"

usage() { sed -n '5,7s/^# \{0,3\}//p' "$0" >&2; }

# Is everything pvbatch needs there? Prints the reason when not.
check() {
  local f
  for f in "$PVBATCH" "$PVLIB/libvtkRemotingCore-pv5.11.so.1" "$PVPY/paraview/simple.py" \
           "$PVPY/vtkmodules/__init__.py"; do
    [ -e "$f" ] || { echo "ParaView (pvbatch) is not installed: missing $f; run scripts/install-paraview.sh"; return 1; }
  done
  command -v xvfb-run >/dev/null || { echo "xvfb-run is missing; run scripts/install-paraview.sh"; return 1; }
  command -v xauth >/dev/null || { echo "xauth is missing; run scripts/install-paraview.sh"; return 1; }
}

# Runs pvbatch from the prefix in a clean environment under a throw-away X server
# (Debian's ParaView renders through GLX only: no EGL/OSMesa, so it needs an X display;
# -noreset: pvbatch disconnects once while probing OpenGL, and a resetting server then refuses
# its next connection, "bad X server connection", SIGABRT). -n: a random first display number
# (xvfb-run -a then counts up from it), so that renders started together rarely pick the same;
# callers retry when Xvfb still lost that race.
# The prefix's vtkmodules must come before python3-vtk9's in /usr/lib/python3/dist-packages,
# and no other Python (pyenv, venv) may leak in: pvbatch embeds Debian's libpython3.11.
pvbatch() {
  env -u PYTHONHOME -u PYTHONSTARTUP -u VIRTUAL_ENV \
    PYTHONPATH="$PVPY" PYTHONNOUSERSITE=1 \
    LD_LIBRARY_PATH="$PVLIB${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" \
    PATH="$PREFIX/usr/bin:/usr/sbin:/usr/bin:/sbin:/bin" \
    xvfb-run -a -n $((100 + RANDOM % 900)) -s "-screen 0 1920x1080x24 -noreset -nolisten tcp" \
    "$PVBATCH" "$@"
}

case "${1:-}" in
  --check)   # installed and smoke-tested by install-paraview.sh
    check >&2 || exit 1
    [ -f "$PREFIX/.flexsens-installed" ] ||
      { echo "ParaView in $PREFIX is incomplete; run scripts/install-paraview.sh" >&2; exit 1; }
    exit 0 ;;
  --selftest)
    reason="$(check)" || { echo "$reason" >&2; exit 1; }
    tmp="$(mktemp -d /tmp/flexsens-pvtest.XXXXXX)"
    trap 'rm -rf "$tmp"' EXIT
    cat > "$tmp/t.py" <<'EOF'
import sys
from paraview.simple import GetParaViewVersion, Sphere, Show, Render, SaveScreenshot
import vtkmodules
if '/opt' not in vtkmodules.__file__ and 'flexsens' not in vtkmodules.__file__:
    print('wrong vtkmodules: ' + vtkmodules.__file__); sys.exit(1)
Show(Sphere()); Render()
SaveScreenshot(sys.argv[1], ImageResolution=[64, 64])
print('pvbatch %s renders headless' % GetParaViewVersion())
EOF
    for _ in 1 2 3; do
      rc=0
      out="$(pvbatch "$tmp/t.py" "$tmp/t.png" 2>&1)" || rc=$?
      grep -q 'Xvfb failed to start' <<<"$out" || break
    done
    [ "$rc" = 0 ] || { echo "$out" >&2; exit 1; }
    [ -s "$tmp/t.png" ] || { echo "$out" >&2; echo "no screenshot written" >&2; exit 1; }
    grep -o 'pvbatch .* renders headless' <<<"$out"
    exit 0 ;;
  -h|--help|"")
    usage; [ -n "${1:-}" ]; exit $? ;;
esac

[ $# -ge 2 ] || { usage; exit 1; }
reason="$(check)" || { echo "render-frames: $reason" >&2; exit 1; }
RUN_DIR="$1"; OUT_DIR="$2"; shift 2
[ -f "$RUN_DIR/frames.pvd" ] || { echo "render-frames: no frames.pvd in $RUN_DIR" >&2; exit 1; }
mkdir -p "$OUT_DIR"
RUN_DIR="$(cd "$RUN_DIR" && pwd)"; OUT_DIR="$(cd "$OUT_DIR" && pwd)"
log="$(mktemp /tmp/flexsens-render.XXXXXX)"
trap 'rm -f "$log"' EXIT
# pvbatch chatters on stderr (Xvfb, MPI); show it only when rendering fails.
for _ in 1 2 3; do
  rc=0
  pvbatch "$HERE/render_frames.py" "$RUN_DIR" "$OUT_DIR" "$@" >"$log" 2>&1 || rc=$?
  grep -q 'Xvfb failed to start' "$log" || break
done
if [ "$rc" = 0 ]; then
  grep -v -e '^_XSERVTransmkdir' -e '^(EE)' "$log" || true
else
  cat "$log" >&2
  exit "$rc"
fi
