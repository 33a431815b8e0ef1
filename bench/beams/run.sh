#!/bin/bash
# Bathe-Bolourchi 45-degree bend with ancf_beam, N = 4 ... 64 elements: the tip against the
# published one and the CPU time per run. Usage: bench/beams/run.sh [build/flexsens]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
flexsens=${1:-$here/../../build/flexsens}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
python3 "$here/bathe_bolourchi.py" "$flexsens" "$out" 4 8 16 32 64
