#!/usr/bin/env bash
# The main job: install, build in Release, run the five-bar study (rigid cases R1-R3, flexible
# cases F1-F6 and their F-R twins), the seed-000 double pendulum and four-bar, the satellite's
# SAT1/SAT2 deployment; plot; render the satellite with ParaView; say where the results are.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
./build/flexsens run examples/fivebar/rigid.yaml
./build/flexsens run examples/fivebar/flexible.yaml
/usr/bin/python3 scripts/plot_fivebar.py results
./build/flexsens run examples/seed000/double_pendulum.yaml
./build/flexsens run examples/seed000/four_bar.yaml
./build/flexsens run examples/satellite/satellite.yaml
# Figure 12's other half: the same cases without numerical damping of the panels' motion.
./build/flexsens run examples/satellite/satellite.yaml --integrator generalized_alpha --dt 0.001 \
  --out results/satellite_galpha
/usr/bin/python3 scripts/plot_satellite.py results
bash scripts/install-paraview.sh
bash scripts/render-frames.sh results/satellite/SAT2 results/satellite/SAT2/png L_B1B2 --every 5
echo "flexsens: results in results/fivebar_rigid/<case>/, results/fivebar_flexible/<case>/,"
echo "          results/double_pendulum/, results/four_bar/, results/satellite/SAT1|SAT2/"
echo "          (frames.pvd for ParaView, series.csv, summary.json); plots in results/plots/;"
echo "          ParaView frames of the deployment in results/satellite/SAT2/png/"
