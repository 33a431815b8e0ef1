#!/usr/bin/env bash
# The whole test suite: install, build, run every test under CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
# ParaView (pvbatch, private prefix: see scripts/PARAVIEW.md) so that the rendering test runs
# instead of skipping.
bash scripts/install-paraview.sh
cd build
ctest --output-on-failure -j 2 --timeout 900
