#!/usr/bin/env bash
# The long form of the scene fuzzer: 3000 mutations (fixed seed) of every example and test
# scene; prints the counts per outcome and the failures (kept in bench/fuzz_failures/).
set -euo pipefail
cd "$(dirname "$0")/.."
python3 scripts/fuzz_scenes.py --exe build/flexsens --count "${1:-3000}" --seed 13 --time-limit 30 \
  --keep bench/fuzz_failures
