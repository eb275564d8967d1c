#!/usr/bin/env bash
# What DDS Security costs: the default battle (6,000 NPCs, 30 Hz) with 50 and with 200 bots, each
# run with security off and then on under each governance protection mode (throng-pki init
# --protection; default: all three), server and bots on this host over 127.0.0.1. Prints per run: server CPU (cores busy while the bots play), tick
# p50/p99, latency p50/p99 in ticks, missed snapshots, and snapshot payload kbit/s per client.
# Knobs (environment): BUILD (default build/release), DOMAIN (default 63), SECONDS_PER_RUN (30),
# BOTS (default "50 200"), PROTECTIONS (default "strict origin rtps").
# Run it on a quiet machine: timings measure the machine as much as the code.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build/release}
DOMAIN=${DOMAIN:-63}
SECS=${SECONDS_PER_RUN:-30}
BOTS=${BOTS:-"50 200"}
PROTECTIONS=${PROTECTIONS:-"strict origin rtps"}
for b in throng-server throng-bots throng-pki; do
  [ -x "$BUILD/bin/$b" ] || { echo "measure-security: $BUILD/bin/$b not built" >&2; exit 1; }
done
out=$(mktemp -d /tmp/throng-security.XXXXXX)
echo "measure-security: results in $out (load average now: $(cut -d' ' -f1-3 /proc/loadavg))"
for p in $PROTECTIONS; do
  "$BUILD/bin/throng-pki" init "$out/pki-$p" --protection "$p" >"$out/pki-$p.log" 2>&1
done

cpu_ticks() { awk '{print $14 + $15}' "/proc/$1/stat"; }

# run NAME BOTS [server/bot security args...]
run() {
  local name=$1 bots=$2
  shift 2
  "$BUILD/bin/throng-server" --domain "$DOMAIN" --duration $((SECS + 60)) --admin-port -1 --no-log \
    --summary-json "$out/$name-server.json" "$@" >"$out/$name-server.txt" 2>"$out/$name-server.log" &
  local spid=$!
  sleep 3  # the scene is built before the match starts
  local c0 t0 c1 t1
  c0=$(cpu_ticks "$spid"); t0=$(date +%s.%N)
  "$BUILD/bin/throng-bots" --domain "$DOMAIN" --clients "$bots" --duration "$SECS" --quiet --server-wait 30 \
    --json "$out/$name-bots.json" "$@" >"$out/$name-bots.txt" 2>"$out/$name-bots.log" || true
  c1=$(cpu_ticks "$spid"); t1=$(date +%s.%N)
  kill -TERM "$spid" 2>/dev/null || true
  wait "$spid" || true
  echo "$c0 $c1 $t0 $t1 $(getconf CLK_TCK)" >"$out/$name-cpu.txt"
}

for n in $BOTS; do
  run "off-$n" "$n"
  for p in $PROTECTIONS; do run "$p-$n" "$n" --security "$out/pki-$p"; done
done

python3 - "$out" "$PROTECTIONS" $BOTS <<'PY'
import json, sys
out = sys.argv[1]
modes = sys.argv[2].split()
print(f"{'run':<11} {'server CPU':>10} {'tick p50':>8} {'tick p99':>8} {'lat p50':>8} {'lat p99':>8} {'missed':>6} {'kbit/s/client':>13} {'joined':>6}")
rows = {}
for n in sys.argv[3:]:
    for mode in ["off"] + modes:
        name = f"{mode}-{n}"
        s = json.load(open(f"{out}/{name}-server.json")); b = json.load(open(f"{out}/{name}-bots.json"))
        c0, c1, t0, t1, hz = open(f"{out}/{name}-cpu.txt").read().split()
        cores = (float(c1) - float(c0)) / float(hz) / (float(t1) - float(t0))
        period = 1000.0 / s["tick_hz"]
        lat = b["latency_ms"]
        rows[name] = cores
        print(f"{name:<11} {cores:>9.2f}c {s['tick_ms']['p50']:>7.2f}ms {s['tick_ms']['p99']:>7.2f}ms "
              f"{lat['p50']/period:>7.2f}t {lat['p99']/period:>7.2f}t {b['snapshot_gap_ticks']:>6} "
              f"{b['kbit_per_s_per_client']['mean']:>13.1f} {b['joined']:>3}/{b['clients']}")
    for m in modes:
        print(f"  {n} bots, {m}: security costs the server {100.0 * (rows[f'{m}-{n}'] / rows[f'off-{n}'] - 1.0):+.0f}% CPU")
PY
