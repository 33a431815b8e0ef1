#!/usr/bin/env bash
# Runs every example scene with two flexsens binaries and compares their outputs byte for byte:
# series.csv of every case, and the VTK frames (frame_*.vtu, frames.pvd). For refactorings that
# must not move a single digit.
#
#   bench/series_identical.sh OLD_EXE NEW_EXE [--steps N] [--variants] [--keep DIR] [SCENE ...]
#
# --steps    each run ends after N of the scene's fixed steps dt (default 5; a scene without dt,
#            IDAS: 1e-3 s steps), or at the scene's t_end when that comes first
# --variants also run each dynamic scene with every fixed-step scheme, full and modified
#            Newton, projections, IDAS, Maggi RK4 and the ad/nd sensitivity methods
# --keep     write the runs under DIR (default: a temporary directory, removed at the end)
# Static scenes (no integrator) run `flexsens static`. A run that fails with one binary must
# fail with the same exit code with the other; its files are compared all the same.
# Exit 0 when everything compared is identical, 1 otherwise (each difference listed).
set -u
old_exe=$(realpath "$1"); new_exe=$(realpath "$2"); shift 2
steps=5; variants=0; keep=""; scenes=()
while [ $# -gt 0 ]; do
  case "$1" in
    --steps) steps=$2; shift 2 ;;
    --variants) variants=1; shift ;;
    --keep) keep=$2; shift 2 ;;
    -*) echo "unknown option $1" >&2; exit 2 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
root=$(cd "$(dirname "$0")/.." && pwd)
[ ${#scenes[@]} -eq 0 ] && mapfile -t scenes < <(cd "$root" && find examples -name '*.yaml' | sort)

# End time of a short run of scene $1: N steps of its dt (1e-3 s without one), at most t_end.
short_end() {
  python3 - "$root/$1" "$steps" <<'PY'
import sys, yaml
scene = yaml.safe_load(open(sys.argv[1])) or {}
integ = scene.get("integrator") or {}
dt = float(integ.get("dt", 1e-3))
print(repr(min(float(integ.get("t_end", 1.0)), int(sys.argv[2]) * dt)))
PY
}
work=${keep:-$(mktemp -d)}
mkdir -p "$work"
[ -z "$keep" ] && trap 'rm -rf "$work"' EXIT

# name|options for `flexsens run` (the scene's own settings first)
run_variants=("scene|")
if [ "$variants" = 1 ]; then
  run_variants+=(
    "trapezoidal|--integrator trapezoidal"
    "trapezoidal_modified|--integrator trapezoidal --newton modified"
    "trapezoidal_projections|--integrator trapezoidal --projections on"
    "bdf1|--integrator bdf1"
    "bdf1_modified|--integrator bdf1 --newton modified"
    "midpoint|--integrator midpoint"
    "galpha|--integrator generalized_alpha --rho-inf 0.8"
    "galpha_projections_modified|--integrator generalized_alpha --projections on --newton modified"
    "idas|--integrator idas --rtol 1e-6"
    "maggi|--integrator maggi_rk4"
    "trapezoidal_ad|--integrator trapezoidal --method ad"
    "trapezoidal_nd|--integrator trapezoidal --method nd")
fi

status=0; compared=0; bytes=0; runs=0
compare_dirs() {  # old_dir new_dir label
  local f rel
  while IFS= read -r f; do
    rel=${f#"$1"/}
    if [ ! -f "$2/$rel" ]; then echo "MISSING in new: $3 $rel"; status=1; continue; fi
    if cmp -s "$f" "$2/$rel"; then
      compared=$((compared + 1)); bytes=$((bytes + $(stat -c %s "$f")))
    else
      echo "DIFFERENT: $3 $rel"; status=1
    fi
  done < <(find "$1" -type f \( -name series.csv -o -name '*.vtu' -o -name '*.pvd' \) | sort)
  while IFS= read -r f; do
    rel=${f#"$2"/}
    [ -f "$1/$rel" ] || { echo "MISSING in old: $3 $rel"; status=1; }
  done < <(find "$2" -type f \( -name series.csv -o -name '*.vtu' -o -name '*.pvd' \) | sort)
}

for scene in "${scenes[@]}"; do
  label=${scene#examples/}; label=${label%.yaml}; label=${label//\//_}
  if grep -qE '^integrator:' "$root/$scene"; then
    t_end=$(short_end "$scene")
    for v in "${run_variants[@]}"; do
      name=${v%%|*}; opts=${v#*|}
      for side in old new; do
        exe=$old_exe; [ $side = new ] && exe=$new_exe
        out="$work/$side/$label/$name"
        rm -rf "$out"; mkdir -p "$out"
        # shellcheck disable=SC2086
        (cd "$root" && "$exe" run "$scene" --out "$out" --t-end "$t_end" $opts >"$out.log" 2>&1)
        echo $? >"$out.rc"
      done
      runs=$((runs + 1))
      if ! cmp -s "$work/old/$label/$name.rc" "$work/new/$label/$name.rc"; then
        echo "EXIT CODES differ: $label $name ($(cat "$work/old/$label/$name.rc") vs $(cat "$work/new/$label/$name.rc"))"
        status=1
      fi
      compare_dirs "$work/old/$label/$name" "$work/new/$label/$name" "$label/$name"
    done
  else
    for side in old new; do
      exe=$old_exe; [ $side = new ] && exe=$new_exe
      out="$work/$side/$label/static"
      rm -rf "$out"; mkdir -p "$out"
      (cd "$root" && "$exe" static "$scene" --out "$out" >"$out.log" 2>&1)
      echo $? >"$out.rc"
    done
    runs=$((runs + 1))
    cmp -s "$work/old/$label/static.rc" "$work/new/$label/static.rc" ||
      { echo "EXIT CODES differ: $label static"; status=1; }
    compare_dirs "$work/old/$label/static" "$work/new/$label/static" "$label/static"
  fi
done
echo "$runs runs, $compared files identical ($bytes bytes)$([ $status = 0 ] && echo ', no differences')"
exit $status
