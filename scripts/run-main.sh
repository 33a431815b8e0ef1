#!/usr/bin/env bash
# The main job: install, build in Release, run the default study, say where results are.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
./build/flexsens run examples/fivebar/rigid.yaml
echo "flexsens: open results/fivebar_rigid/frames.pvd in ParaView; series.csv and summary.json beside it"
