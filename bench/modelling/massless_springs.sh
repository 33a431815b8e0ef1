#!/usr/bin/env bash
# Massless springs against the paper's massed springs: the satellite's nominal motion over
# 10 s, BDF-1 at dt 0.02 s (the paper's scheme) for both; prints each output's largest
# difference relative to its range in the massed run. Results: massless_springs.md.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$(mktemp -d)
build/flexsens run examples/satellite/satellite.yaml --case SAT1 --out "$out/massed" > /dev/null
build/flexsens run examples/satellite/satellite_massless.yaml --integrator bdf1 --dt 0.02 --out "$out/massless" > /dev/null
python3 - "$out" <<'PY'
import csv, sys
d = sys.argv[1]
A = list(csv.DictReader(open(d + '/massed/SAT1/series.csv')))
B = list(csv.DictReader(open(d + '/massless/series.csv')))
assert [r['t'] for r in A] == [r['t'] for r in B]
for key in ['xB2', 'open1', 'open2', 'open3', 'open4']:
    a = [float(r[key]) for r in A]; b = [float(r[key]) for r in B]
    rng = max(a) - min(a); diff = max(abs(x - y) for x, y in zip(a, b))
    print(f"{key}: range {rng:.5g}, max |massless - massed| {diff:.3g} ({100 * diff / rng:.3g}% of the range)")
PY
rm -rf "$out"
