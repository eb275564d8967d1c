#!/usr/bin/env bash
# Measures the server and load-test targets (issues 3 and 4) on this machine, server and bots on
# the same host over DDS on 127.0.0.1, and prints the figures the closing notes quote:
#   1. the default battle (6,000 NPCs, 30 Hz) with 50 bot clients for MATCH_S seconds (default 60):
#      tick p50/p99/max, overruns, bytes per pose, kbit/s per client, latency;
#   2. 200 bot clients against a 5,000-NPC battle for LOAD_S seconds (default 30): latency in ticks;
#   3. ramp mode from RAMP_START (default 150) in steps of RAMP_STEP (default 25) up to RAMP_MAX
#      (default 300), with a perf profile of the server over the last step when perf is installed.
# The server writes its match log (keyframes included), as it does by default.
# Run it on a quiet machine (no build running): timings measure the machine as much as the code.
# Knobs (environment): BUILD (default build/release), DOMAIN (default 61), MATCH_S, LOAD_S,
# RAMP_START, RAMP_STEP, RAMP_MAX, SKIP (comma-separated: match,load,ramp), SERVER_ARGS (more
# throng-server flags for the match and load runs, e.g. "--scene FILE" to compare settings).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build/release}
DOMAIN=${DOMAIN:-61}
MATCH_S=${MATCH_S:-60}
LOAD_S=${LOAD_S:-30}
RAMP_START=${RAMP_START:-150}
RAMP_STEP=${RAMP_STEP:-25}
RAMP_MAX=${RAMP_MAX:-300}
SKIP=${SKIP:-}
for b in throng-server throng-bots; do
  [ -x "$BUILD/bin/$b" ] || { echo "measure-server: $BUILD/bin/$b not built (cmake --build $BUILD --target $b)" >&2; exit 1; }
done
out=$(mktemp -d /tmp/throng-measure.XXXXXX)
echo "measure-server: results in $out (load average now: $(cut -d' ' -f1-3 /proc/loadavg))"

# run_match NAME NPCS BOTS SECONDS [extra bot args...]: server for SECONDS + 20 s, bots for SECONDS.
run_match() {
  local name=$1 npcs=$2 bots=$3 secs=$4
  shift 4
  "$BUILD/bin/throng-server" --domain "$DOMAIN" --npcs "$npcs" --duration $((secs + 40)) --admin-port -1 \
    --log "$out/$name.tlog" --summary-json "$out/$name-server.json" ${SERVER_ARGS:-} >"$out/$name-server.txt" 2>"$out/$name-server.log" &
  local spid=$!
  "$BUILD/bin/throng-bots" --domain "$DOMAIN" --clients "$bots" --duration "$secs" --quiet \
    --json "$out/$name-bots.json" "$@" >"$out/$name-bots.txt" 2>"$out/$name-bots.log" || true
  kill -TERM "$spid" 2>/dev/null || true
  wait "$spid" || true
}

summarise() {
  python3 - "$out/$1-server.json" "$out/$1-bots.json" "$2" <<'PY'
import json, sys
s = json.load(open(sys.argv[1])); b = json.load(open(sys.argv[2])); label = sys.argv[3]
period = 1000.0 / s["tick_hz"]
t = s["tick_ms"]; ph = s["phase_ms"]; lat = b["latency_ms"]
print(f"{label}: {s['bodies']} bodies, {b['joined']}/{b['clients']} bots, {s['ticks']} ticks")
print(f"  tick ms p50 {t['p50']:.2f} p99 {t['p99']:.2f} max {t['max']:.2f} (25% of the period = {period/4:.2f}); "
      f"overruns {s['overruns']}")
print("  phases p50/p99 ms: " + ", ".join(f"{k} {v['p50']:.2f}/{v['p99']:.2f}" for k, v in ph.items()))
print(f"  snapshots {s['snapshots']['bytes_per_pose']:.2f} bytes/pose, "
      f"{b['kbit_per_s_per_client']['mean']:.1f} kbit/s per client, missed {b['snapshot_gap_ticks']}")
print(f"  latency ms p50 {lat['p50']:.1f} ({lat['p50']/period:.2f} ticks) p90 {lat['p90']:.1f} "
      f"p99 {lat['p99']:.1f} ({lat['p99']/period:.2f} ticks) max {lat['max']:.1f}")
PY
}

if [[ ",$SKIP," != *",match,"* ]]; then
  echo "=== 1. default battle, 50 bots, ${MATCH_S} s"
  run_match match 6000 50 "$MATCH_S" --behavior mix
  summarise match "default battle + 50 bots"
fi
if [[ ",$SKIP," != *",load,"* ]]; then
  echo "=== 2. 5,000 NPCs, 200 bots, ${LOAD_S} s"
  run_match load 5000 200 "$LOAD_S" --behavior mix
  summarise load "5,000 NPCs + 200 bots"
fi
if [[ ",$SKIP," != *",ramp,"* ]]; then
  echo "=== 3. ramp ${RAMP_START} +${RAMP_STEP} .. ${RAMP_MAX} (5,000 NPCs)"
  steps=$(( (RAMP_MAX - RAMP_START) / RAMP_STEP + 1 ))
  "$BUILD/bin/throng-server" --domain "$DOMAIN" --npcs 5000 --duration $((steps * 20 + 60)) --admin-port -1 \
    --log "$out/ramp.tlog" --max-clients 4096 >"$out/ramp-server.txt" 2>"$out/ramp-server.log" &
  spid=$!
  perf_pid=
  if command -v perf >/dev/null; then
    # Profile the server over the whole ramp (stopped when the bots are done): the ramp spends
    # most of its time in its upper steps, next to the ceiling.
    perf record -e cpu-clock -F 499 -p "$spid" -o "$out/ramp-perf.data" >/dev/null 2>&1 &
    perf_pid=$!
  fi
  "$BUILD/bin/throng-bots" --domain "$DOMAIN" --ramp --ramp-start "$RAMP_START" --ramp-step "$RAMP_STEP" \
    --ramp-max "$RAMP_MAX" --ramp-step-s 8 --quiet --json "$out/ramp-bots.json" >"$out/ramp-bots.txt" 2>"$out/ramp-bots.log" || true
  [ -n "$perf_pid" ] && { kill -INT "$perf_pid" 2>/dev/null || true; wait "$perf_pid" || true; }
  kill -TERM "$spid" 2>/dev/null || true
  wait "$spid" || true
  grep -E "^ramp" "$out/ramp-bots.log" || true
  grep -iE "ramp|ceiling|sustain" "$out/ramp-bots.txt" | head -5 || true
  if [ -f "$out/ramp-perf.data" ]; then
    echo "  server CPU by function (perf, top 12):"
    perf report -i "$out/ramp-perf.data" --no-children --sort dso,symbol 2>/dev/null | grep -E "^ +[0-9]" | head -12 |
      sed -E 's/ +/ /g; s/^/   /' | cut -c1-150
  fi
fi
echo "measure-server: raw outputs in $out"
