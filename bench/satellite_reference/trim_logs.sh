#!/usr/bin/env bash
# Keeps what analyze.py reads from runs/*/ (series.csv, summary.json, cpu.txt) and the last
# lines of each run.log without its progress bar, so the results can be committed.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
for d in "$here"/runs/*/; do
  [ -f "$d/run.log" ] || continue
  tr '\r' '\n' < "$d/run.log" | grep -v 'elapsed$' | grep -v '^ *$' | tail -4 > "$d/run.log.tmp"
  mv "$d/run.log.tmp" "$d/run.log"
  rm -f "$d"/.*.lock "$d"/*/frames.pvd
done
