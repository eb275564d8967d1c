#!/usr/bin/env bash
# The README's first quick-start command: installs dependencies, builds the Release binaries and
# hosts the default match on this machine: throng-server on the built-in battle scene (6,000 NPCs,
# 30 Hz) with simulated bot clients joining over DDS on 127.0.0.1. Prints the bots' report and the
# server's summary at the end.
#
# Knobs (environment): BOTS (default 50), DURATION seconds of bot play (default 20),
# THRONG_DOMAIN (default 42), BEHAVIOR (default mix), BUILD dir (default build/release).
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/install-deps.sh
BUILD=${BUILD:-build/release}
BOTS=${BOTS:-50}
DURATION=${DURATION:-20}
DOMAIN=${THRONG_DOMAIN:-42}
BEHAVIOR=${BEHAVIOR:-mix}
cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target throng-server throng-bots

out=$(mktemp -d /tmp/throng-demo.XXXXXX)
echo "=== throng-server (logs: $out/server.log)"
# The server would stop by itself after DURATION + 30 s; normally the script ends it with SIGTERM
# (a graceful shutdown) as soon as the bots are done.
"$BUILD/bin/throng-server" --domain "$DOMAIN" --duration $((DURATION + 30)) --admin-port 0 \
  --summary-json "$out/server.json" >"$out/server.txt" 2>"$out/server.log" &
server_pid=$!
trap 'kill -TERM $server_pid 2>/dev/null || true' EXIT

echo "=== throng-bots: $BOTS clients for $DURATION s"
bots_status=0
"$BUILD/bin/throng-bots" --domain "$DOMAIN" --clients "$BOTS" --duration "$DURATION" --behavior "$BEHAVIOR" \
  --json "$out/bots.json" || bots_status=$?

kill -TERM "$server_pid" 2>/dev/null || true
server_status=0
wait "$server_pid" || server_status=$?
trap - EXIT
cat "$out/server.txt"
echo "JSON reports: $out/bots.json $out/server.json"
if [ "$bots_status" -ne 0 ] || [ "$server_status" -ne 0 ]; then
  echo "demo failed: bots exit $bots_status, server exit $server_status (server log: $out/server.log)" >&2
  tail -n 20 "$out/server.log" >&2
  exit 1
fi
