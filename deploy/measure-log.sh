#!/usr/bin/env bash
# Measures the match log of a real battle (issue figures: size per tick, verify speed, seek time):
# the default battle (6,000 NPCs, 30 Hz) with 50 bots of mixed behaviours for SECONDS (default 300),
# server and bots on this machine over DDS on 127.0.0.1, the log written as the server does by
# default. Then, on that log:
#   - bytes per tick (whole file, keyframes, inputs) from `throng-replay info --json`;
#   - `verify --jobs 1` and `--jobs 2`, wall time and times real time;
#   - seeks to the tick before each 5th keyframe's successor (59 ticks past a keyframe: the longest
#     re-simulation), median and max of the times `throng-replay seek` reports.
# Run it on a quiet machine: timings measure the machine as much as the code.
# Usage: deploy/measure-log.sh [SECONDS]   (env: BUILD=build/release, DOMAIN=63, BOTS=50, NPCS=6000, OUT=dir)
set -euo pipefail
cd "$(dirname "$0")/.."
SECS=${1:-300}
BUILD=${BUILD:-build/release}
DOMAIN=${DOMAIN:-63}
BOTS=${BOTS:-50}
NPCS=${NPCS:-6000}
if ! [[ "$SECS" =~ ^[0-9]+$ ]] || [ "$SECS" -lt 10 ]; then
  echo "measure-log: SECONDS must be a whole number >= 10 (got '$SECS')" >&2
  exit 2
fi
for b in throng-server throng-bots throng-replay; do
  [ -x "$BUILD/bin/$b" ] || { echo "measure-log: $BUILD/bin/$b not built (cmake --build $BUILD)" >&2; exit 2; }
done
command -v python3 >/dev/null || { echo "measure-log: python3 is needed to read the JSON" >&2; exit 2; }
OUT=${OUT:-$(mktemp -d /tmp/throng-measure-log.XXXXXX)}
mkdir -p "$OUT"
LOG="$OUT/battle.tlog"
echo "measure-log: ${SECS} s of the default battle ($NPCS NPCs) with $BOTS bots; results in $OUT (load now: $(cut -d' ' -f1-3 /proc/loadavg))"

"$BUILD/bin/throng-server" --domain "$DOMAIN" --npcs "$NPCS" --duration $((SECS + 40)) --admin-port -1 \
  --log "$LOG" --summary-json "$OUT/server.json" >"$OUT/server.txt" 2>"$OUT/server.log" &
SERVER=$!
trap 'kill -TERM $SERVER 2>/dev/null || true' EXIT
"$BUILD/bin/throng-bots" --domain "$DOMAIN" --clients "$BOTS" --behavior mix --duration "$SECS" --quiet --server-wait 30 \
  --json "$OUT/bots.json" >"$OUT/bots.txt" 2>"$OUT/bots.log" || true
kill -TERM "$SERVER" 2>/dev/null || true
wait "$SERVER" || true
trap - EXIT

"$BUILD/bin/throng-replay" info "$LOG" --json >"$OUT/info.json"
python3 - "$OUT/info.json" <<'EOF'
import json, sys
j = json.load(open(sys.argv[1]))
ticks = max(1, j["ticks"])
kf = j.get("keyframe_bytes", 0)
print(f"size: {j['file_bytes'] / ticks:.0f} bytes/tick whole file ({j['file_bytes'] / 1e6:.1f} MB, {ticks} ticks); "
      f"keyframes {kf / ticks:.0f} bytes/tick ({j.get('keyframes', 0)} of them, {kf / max(1, j.get('keyframes', 1)) / 1e3:.0f} kB each, "
      f"baselines {'kept' if j.get('keyframe_snapshot_baselines') else 'left out'}); the rest {(j['file_bytes'] - kf) / ticks:.0f} bytes/tick")
EOF

TICK_HZ=$(python3 -c "import json; print(json.load(open('$OUT/info.json'))['tick_hz'])")
TICKS=$(python3 -c "import json; print(json.load(open('$OUT/info.json'))['ticks'])")
for jobs in 1 2; do
  start=$(date +%s.%N)
  "$BUILD/bin/throng-replay" verify "$LOG" --jobs "$jobs" >"$OUT/verify$jobs.txt" 2>&1 || {
    echo "measure-log: verify --jobs $jobs FAILED (see $OUT/verify$jobs.txt)"; continue; }
  end=$(date +%s.%N)
  python3 -c "w=$end-$start; print(f'verify --jobs $jobs: {w:.1f} s for $TICKS ticks = {$TICKS/$TICK_HZ/w:.1f}x real time')"
done

# The longest seeks: 59 ticks past every 5th keyframe.
python3 - "$OUT/info.json" >"$OUT/seek_ticks.txt" <<'EOF'
import json, sys
j = json.load(open(sys.argv[1]))
every = j.get("keyframe_interval_ticks", 0)
last = j.get("last_keyframe_tick", 0)
if every > 0:
    for k in range(every, last, every * 5):
        print(k + every - 1)
EOF
: >"$OUT/seek_ms.txt"
while read -r t; do
  "$BUILD/bin/throng-replay" seek "$LOG" --tick "$t" >"$OUT/seek.txt" 2>&1 || { echo "measure-log: seek --tick $t FAILED"; cat "$OUT/seek.txt"; continue; }
  sed -n 's/.* in \([0-9.]*\) ms$/\1/p' "$OUT/seek.txt" >>"$OUT/seek_ms.txt"
done <"$OUT/seek_ticks.txt"
python3 - "$OUT/seek_ms.txt" <<'EOF'
import sys, statistics
v = sorted(float(x) for x in open(sys.argv[1]) if x.strip())
if v:
    print(f"seek 59 ticks past a keyframe: median {statistics.median(v):.0f} ms, max {v[-1]:.0f} ms over {len(v)} seeks")
else:
    print("seek: no keyframes to seek past")
EOF
