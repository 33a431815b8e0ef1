#!/usr/bin/env bash
# The main job: install, build in Release, run the five-bar study (rigid cases R1-R3, flexible
# cases F1-F6 and their F-R twins), plot dz2/dp, and say where the results are.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
./build/flexsens run examples/fivebar/rigid.yaml
./build/flexsens run examples/fivebar/flexible.yaml
/usr/bin/python3 scripts/plot_fivebar.py results
echo "flexsens: results in results/fivebar_rigid/<case>/ and results/fivebar_flexible/<case>/"
echo "          (frames.pvd for ParaView, series.csv, summary.json); plots in results/plots/"
