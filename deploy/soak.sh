#!/usr/bin/env bash
# Soak: the default battle for MINUTES (default 60) with 100 bots of mixed behaviours, 80 for the
# whole run and 20 that leave and rejoin every minute, the match log on. Every 10 s it samples the
# server's RSS, its tick p50/p99 over the last 10 s and overruns (from its progress line), and the
# match log's size (/metrics), into soak.csv; at the end it draws soak.svg, verifies the log, and
# prints one verdict line against the targets:
#   RSS growth after the first 5 minutes < 1%; tick p99 of the last 10 minutes at most 10% above
#   the first 10 (a faster end is no failure: the first minutes include every bot's join); no
#   snapshot gap at any bot; the log verifies.
# Runs shorter than 30 minutes scale those windows to a twelfth (RSS baseline) and a sixth (p99)
# of the run. Exit 0 when every target holds, 1 otherwise, 2 on a setup error.
# Usage: deploy/soak.sh [MINUTES]   (env: BUILD=build/release, DOMAIN=62, OUT=dir, NPCS=6000,
#   SERVER_ARGS: more throng-server flags, e.g. "--trim-memory-every 0" to soak without trims)
set -euo pipefail
cd "$(dirname "$0")/.."
MINUTES=${1:-60}
BUILD=${BUILD:-build/release}
DOMAIN=${DOMAIN:-62}
NPCS=${NPCS:-6000}
ADMIN_PORT=${ADMIN_PORT:-9471}
if ! [[ "$MINUTES" =~ ^[0-9]+$ ]] || [ "$MINUTES" -lt 1 ]; then
  echo "soak: MINUTES must be a whole number of minutes >= 1 (got '$MINUTES')" >&2
  exit 2
fi
for b in throng-server throng-bots throng-replay; do
  [ -x "$BUILD/bin/$b" ] || { echo "soak: $BUILD/bin/$b not built (cmake --build $BUILD)" >&2; exit 2; }
done
OUT=${OUT:-$(mktemp -d /tmp/throng-soak.XXXXXX)}
mkdir -p "$OUT"
SECONDS_TOTAL=$((MINUTES * 60))
echo "soak: $MINUTES min, $NPCS NPCs, 100 bots (20 rejoining every minute); results in $OUT"

"$BUILD/bin/throng-server" --domain "$DOMAIN" --npcs "$NPCS" --duration $((SECONDS_TOTAL + 30)) \
  --admin-port "$ADMIN_PORT" --log "$OUT/soak.tlog" --summary-json "$OUT/server.json" ${SERVER_ARGS:-} \
  >"$OUT/server.txt" 2>"$OUT/server.log" &
SERVER=$!
PIDS=()
cleanup() {
  for p in "${PIDS[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
  kill -TERM "$SERVER" 2>/dev/null || true
}
trap cleanup EXIT

# The steady 80, then waves of 20 (each wave 50 s, a new one every minute).
"$BUILD/bin/throng-bots" --domain "$DOMAIN" --clients 80 --behavior mix --duration "$SECONDS_TOTAL" --quiet \
  --server-wait 30 --name-prefix steady --json "$OUT/bots-steady.json" >"$OUT/bots-steady.txt" 2>"$OUT/bots-steady.log" &
PIDS+=($!)
(
  wave=0
  while [ $((wave * 60 + 50)) -le "$SECONDS_TOTAL" ]; do
    "$BUILD/bin/throng-bots" --domain "$DOMAIN" --clients 20 --behavior mix --duration 50 --quiet --server-wait 30 \
      --seed $((wave + 1)) --name-prefix "wave$wave" --json "$OUT/bots-wave$wave.json" \
      >"$OUT/bots-wave$wave.txt" 2>"$OUT/bots-wave$wave.log" || true
    wave=$((wave + 1))
    sleep 8
  done
) &
PIDS+=($!)

echo "t_s,rss_kb,tick_p50_ms,tick_p99_ms,overruns,log_bytes,clients" >"$OUT/soak.csv"
start=$(date +%s)
while :; do
  sleep 10
  now=$(( $(date +%s) - start ))
  # The bots stop at SECONDS_TOTAL: a sample taken while they leave is not the soak's.
  [ "$now" -gt $((SECONDS_TOTAL - 5)) ] && break
  kill -0 "$SERVER" 2>/dev/null || { echo "soak: the server exited early (see $OUT/server.log)" >&2; break; }
  rss=$(awk '/^VmRSS:/ {print $2}' "/proc/$SERVER/status" 2>/dev/null || echo 0)
  # The progress line (every 10 s): "... | last 10 s: p50 X ms p99 Y ms | overruns N | ...".
  line=$(grep ' | last ' "$OUT/server.log" | tail -1 || true)
  p50=$(sed -n 's/.*| last [0-9]* s: p50 \([0-9.]*\) ms p99 .*/\1/p' <<<"$line")
  p99=$(sed -n 's/.*| last [0-9]* s: p50 [0-9.]* ms p99 \([0-9.]*\) ms.*/\1/p' <<<"$line")
  overruns=$(sed -n 's/.*| overruns \([0-9]*\) |.*/\1/p' <<<"$line")
  clients=$(sed -n 's/.*| clients \([0-9]*\) |.*/\1/p' <<<"$line")
  metrics=$(curl -s --max-time 2 "http://127.0.0.1:$ADMIN_PORT/metrics" || true)
  log_bytes=$(awk '/^throng_matchlog_bytes / {printf "%d", $2}' <<<"$metrics")
  echo "$now,${rss:-0},${p50:-},${p99:-},${overruns:-},${log_bytes:-},${clients:-}" >>"$OUT/soak.csv"
  if [ $((now % 300)) -lt 10 ]; then
    echo "soak: ${now}s  rss ${rss} kB  tick p99 ${p99:-?} ms  clients ${clients:-?}  log $((${log_bytes:-0} / 1000000)) MB"
  fi
done

for p in "${PIDS[@]}"; do wait "$p" 2>/dev/null || true; done
kill -TERM "$SERVER" 2>/dev/null || true
wait "$SERVER" 2>/dev/null || true
trap - EXIT
verify_ok=0
"$BUILD/bin/throng-replay" verify --jobs 2 "$OUT/soak.tlog" >"$OUT/verify.txt" 2>&1 && verify_ok=1
python3 deploy/soak_report.py "$OUT" "$MINUTES" "$verify_ok"
