#!/usr/bin/env bash
# Regenerates the speed-versus-accuracy report bench/study/study.md (+ CSV, PNG) in one run
# (about 5-7 minutes on 2 cores; `--quick` for a smoke test). FLEXSENS_BUILD_DIR=<dir> builds
# and uses that build directory instead of build/.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${FLEXSENS_BUILD_DIR:-build}"
if [ "$build" = build ]; then
  bash scripts/build.sh
else
  [ -f "$build/build.ninja" ] || cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" -j "$(nproc)" --target flexsens
fi
"./$build/flexsens" study --out bench/study "$@"
/usr/bin/python3 scripts/plot_study.py bench/study
echo "flexsens: report in bench/study/study.md"
