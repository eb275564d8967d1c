#!/usr/bin/env bash
# The worst tick of the crush family (issue: bounded overlap in every tick): every scene at K = 8,
# blocked_motion_carry default and 0, measured every tick from tick 61 by the independent metric.
# Prints a Markdown table for docs/benchmarks.md.
#   deploy/measure-worst-tick.sh [N...=5000 20000] (BIN=build/release/bin/throng-bench)
set -euo pipefail
bench=${BIN:-build/release/bin/throng-bench}
[[ -x $bench ]] || { echo "measure-worst-tick: $bench not found (build Release first)" >&2; exit 2; }
sizes=("$@"); ((${#sizes[@]})) || sizes=(5000 20000)
scenes=(crush server/engine/data/scenes/crush_post.json server/engine/data/scenes/crush_pillars.json mixed)
echo "| scene | N | carry | worst max / r | worst p99 / r | ticks over 0.5 r | median µs | p95 µs |"
echo "|---|---|---|---|---|---|---|---|"
for n in "${sizes[@]}"; do
  for scene in "${scenes[@]}"; do
    for carry in default 0; do
      extra=(); [[ $carry == 0 ]] && extra=(--carry 0)
      "$bench" --scene "$scene" --agents "$n" "${extra[@]}" --json | python3 -c "
import json, sys
j = json.load(sys.stdin); r = j['residual_over_time']; t = j['tick_us']
print('| %s | %s | %s | %.3f | %.3f | %d | %.0f | %.0f |' % ('$(basename "$scene" .json)', '$n', '$carry',
      r['worst_max_pen_over_radius'], r['worst_p99_pen_over_radius'], r['ticks_over_0_5_r'], t['median'], t['p95']))"
    done
  done
done
