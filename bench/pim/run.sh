#!/usr/bin/env bash
# The PIM at growing mesh sizes: `flexsens check` of the shell panel (examples/shell/panel.yaml,
# cases F1 and R) at element sizes 0.025 ... 0.0019 m (n = 192 ... 20070), CPU time and peak
# RSS per size, for each binary given (e.g. an older build beside the current one), and one
# short run of case F1 at the largest size.
#   bench/pim/run.sh build/flexsens [OLD/flexsens]    (results on stdout; results.md keeps them)
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
W="$(mktemp -d)"
trap 'rm -rf "$W"' EXIT
cp "$ROOT/examples/shell/panel.geo" "$W/"
echo "| binary | size [m] | n | m_r F1 | cond(A) F1 | CPU [s] | peak RSS [MB] |"
echo "|---|---|---|---|---|---|---|"
for bin in "$@"; do
  for size in 0.025 0.0125 0.0065 0.005 0.0019; do
    # the dense PIM of older builds is cubic: skip what would take hours
    if [ "$bin" != "$1" ] && [ "$size" = 0.0019 ]; then continue; fi
    sed "s/size: 0.025/size: $size/" "$ROOT/examples/shell/panel.yaml" > "$W/p.yaml"
    out=$(/usr/bin/time -f "TIME %U %M" "$bin" check "$W/p.yaml" 2>&1)
    n=$(echo "$out" | sed -n 's/.*dimension 3, n = \([0-9]*\).*/\1/p')
    mr=$(echo "$out" | sed -n 's/.*case F1:.*m_r = \([0-9]*\).*/\1/p')
    cond=$(echo "$out" | sed -n 's/.*case F1:.*cond(A) = \([0-9.e+]*\).*/\1/p')
    read -r cpu rss < <(echo "$out" | sed -n 's/^TIME \([0-9.]*\) \([0-9]*\)/\1 \2/p')
    echo "| $bin | $size | $n | $mr | $cond | $cpu | $((rss / 1024)) |"
  done
done
sed "s/size: 0.025/size: 0.0019/" "$ROOT/examples/shell/panel.yaml" > "$W/p.yaml"
/usr/bin/time -f "case F1, n = 20070, 2 steps of 1 ms: CPU %U s, peak RSS %M kB" \
  "$1" run "$W/p.yaml" --case F1 --t-end 0.002 --out "$W/run" 2>&1 | tail -2
