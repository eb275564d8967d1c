#!/usr/bin/env bash
# The worst tick of the crush family (issue: bounded overlap in every tick): every scene at K = 8,
# blocked_motion_carry default and 0, measured every tick from tick 61 by the independent metric.
# Prints a Markdown table; with JSON_OUT=FILE also writes every run's
# residual_over_time and tick times as JSON (deploy/make-benchmarks-doc.sh renders them).
#   deploy/measure-worst-tick.sh [N...=5000 20000] (BIN=build/release/bin/throng-bench)
set -euo pipefail
bench=${BIN:-build/release/bin/throng-bench}
[[ -x $bench ]] || { echo "measure-worst-tick: $bench not found (build Release first)" >&2; exit 2; }
sizes=("$@"); ((${#sizes[@]})) || sizes=(5000 20000)
for n in "${sizes[@]}"; do
  [[ $n =~ ^[1-9][0-9]*$ ]] || { echo "measure-worst-tick: N must be a positive whole number, got '$n'" >&2; exit 2; }
done
rows=$(mktemp); trap 'rm -f "$rows"' EXIT
scenes=(crush server/engine/data/scenes/crush_post.json server/engine/data/scenes/crush_pillars.json mixed)
echo "| scene | N | carry | worst max / r | worst p99 / r | ticks over 0.5 r | median µs | p95 µs |"
echo "|---|---|---|---|---|---|---|---|"
for n in "${sizes[@]}"; do
  for scene in "${scenes[@]}"; do
    for carry in default 0; do
      extra=(); [[ $carry == 0 ]] && extra=(--carry 0)
      echo "measure-worst-tick: $(basename "$scene" .json) $n, carry $carry" >&2
      "$bench" --scene "$scene" --agents "$n" "${extra[@]}" --json | python3 -c "
import json, sys
j = json.load(sys.stdin); r = j['residual_over_time']; t = j['tick_us']
print('| %s | %s | %s | %.3f | %.3f | %d | %.0f | %.0f |' % ('$(basename "$scene" .json)', '$n', '$carry',
      r['worst_max_pen_over_radius'], r['worst_p99_pen_over_radius'], r['ticks_over_0_5_r'], t['median'], t['p95']))
with open('$rows', 'a') as f:
    f.write(json.dumps({'scene': '$(basename "$scene" .json)', 'agents': $n, 'carry': '$carry',
                        'residual_over_time': r, 'tick_us': t, 'state_hash': j['state_hash']}) + '\\n')"
    done
  done
done
if [[ -n ${JSON_OUT:-} ]]; then
  python3 -c "
import json, sys
json.dump({'rows': [json.loads(l) for l in open(sys.argv[1])]}, open(sys.argv[2], 'w'), indent=1)" "$rows" "$JSON_OUT"
fi
