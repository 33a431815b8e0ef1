#!/usr/bin/env bash
# The whole test suite: install, build, run every test under CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
cd build
ctest --output-on-failure -j 2 --timeout 900
