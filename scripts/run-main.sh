#!/usr/bin/env bash
# The main job: install, build in Release, run the five-bar study (rigid cases R1-R3, flexible
# cases F1-F6 and their F-R twins), the seed-000 double pendulum and four-bar, the satellite's
# SAT1/SAT2 deployment as the paper ran it and the run flexsens trusts; plot; render the
# satellite with ParaView; print a table of every run's status, reason and what it shows.
#
#   bash scripts/run-main.sh            # the full job (a few minutes)
#   bash scripts/run-main.sh --quick    # the same scenes and table with shorter runs (CI)
#
# Every scene runs to its end whatever its status; the job exits non-zero only for what the
# table does not expect (a crash, a numerical failure, an output error, another status).
set -euo pipefail
cd "$(dirname "$0")/.."
QUICK=()
for a in "$@"; do
  case "$a" in
    --quick) QUICK=(--quick) ;;
    *) echo "usage: bash scripts/run-main.sh [--quick]" >&2; exit 2 ;;
  esac
done
bash scripts/build.sh
status=0
/usr/bin/python3 scripts/main_job.py "${QUICK[@]}" --exe build/flexsens --results results || status=$?
echo
echo "flexsens: results in results/fivebar_rigid/<case>/, results/fivebar_flexible/<case>/,"
echo "          results/double_pendulum/, results/four_bar/, results/satellite/SAT1|SAT2/,"
echo "          results/satellite_trusted/SAT1|SAT2/ (frames.pvd for ParaView, series.csv,"
echo "          summary.json); plots in results/plots/; ParaView frames of the deployment in"
echo "          results/satellite/SAT2/png/"
exit $status
