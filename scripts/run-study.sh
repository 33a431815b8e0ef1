#!/usr/bin/env bash
# Regenerates the speed-versus-accuracy report bench/study/study.md (+ CSV, PNG) in one run.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
./build/flexsens study --out bench/study "$@"
/usr/bin/python3 scripts/plot_study.py bench/study
echo "flexsens: report in bench/study/study.md"
