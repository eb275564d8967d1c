#!/usr/bin/env bash
# Measures the hot standby (issue 19, docs/design/standby.md) on this machine, every process on
# the same host over DDS on 127.0.0.1, and prints the figures the closing notes quote:
#   1. cost: the default battle (6,000 NPCs, 30 Hz) with 20 bots for MATCH_S seconds (default 40),
#      alone and with a standby following it, RUNS times each, alternating: CPU seconds of the
#      primary and of the standby (user + system, /usr/bin/time), tick p50/p99;
#   2. takeover: the same match with a standby; the primary is killed with SIGKILL after KILL_S
#      seconds (default 15); the bots play on: their longest run of missed ticks, their longest
#      wait between two snapshots (ms), commands rejected, whether the new primary kept all 20
#      clients; then `throng-replay verify` of the standby's log (begun at its checkpoint, continued
#      by it as the new primary) and of the killed primary's log.
# Run it on a quiet machine: both processes share its cores with the bots.
# Knobs (environment): BUILD (default build/release), DOMAIN (default 63), MATCH_S, KILL_S, RUNS
# (default 2), BOTS (default 20), NPCS (default 6000).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build/release}
DOMAIN=${DOMAIN:-63}
MATCH_S=${MATCH_S:-40}
KILL_S=${KILL_S:-15}
RUNS=${RUNS:-2}
BOTS=${BOTS:-20}
NPCS=${NPCS:-6000}
for b in throng-server throng-bots; do
  [ -x "$BUILD/bin/$b" ] || { echo "measure-standby: $BUILD/bin/$b not built (cmake --build $BUILD --target $b)" >&2; exit 1; }
done
[ -x /usr/bin/time ] || { echo "measure-standby: /usr/bin/time is missing (apt-get install time)" >&2; exit 1; }
out=$(mktemp -d /tmp/throng-standby.XXXXXX)
echo "measure-standby: results in $out (load average now: $(cut -d' ' -f1-3 /proc/loadavg))"
server=$(realpath "$BUILD/bin/throng-server")
bots=$(realpath "$BUILD/bin/throng-bots")

# run NAME with|without|kill: one match; the standby starts a second after the primary.
run() {
  local name=$1 mode=$2 d="$out/$1"
  mkdir -p "$d"
  # Match logs only where a takeover is measured: the cost runs compare the standby's cost alone.
  local plog=(--no-log) slog=(--no-log)
  if [ "$mode" = kill ]; then plog=(--log "$d/primary.tlog"); slog=(--log "$d/standby.tlog"); fi
  /usr/bin/time -f "%U %S" -o "$d/primary.cpu" "$server" --domain "$DOMAIN" --npcs "$NPCS" "${plog[@]}" \
    --admin-port -1 --duration $((MATCH_S + 4)) --summary-json "$d/primary.json" >"$d/primary.txt" 2>"$d/primary.log" &
  local ppid=$!
  sleep 1
  local spid=""
  if [ "$mode" != without ]; then
    /usr/bin/time -f "%U %S" -o "$d/standby.cpu" "$server" --standby --domain "$DOMAIN" "${slog[@]}" --admin-port -1 \
      --duration $((MATCH_S + 4)) --summary-json "$d/standby.json" >"$d/standby.txt" 2>"$d/standby.log" &
    spid=$!
  fi
  sleep 1
  # --rejoin-after 1: a bot whose snapshots stop for a second joins again; a takeover must cause none.
  "$bots" --domain "$DOMAIN" --clients "$BOTS" --behavior mix --duration "$MATCH_S" --quiet --rejoin-after 1 \
    --json "$d/bots.json" >"$d/bots.txt" 2>"$d/bots.log" &
  local bpid=$!
  if [ "$mode" = kill ]; then
    sleep "$KILL_S"
    # /usr/bin/time's child is the server: kill the server itself, not the wrapper.
    pkill -KILL -P "$ppid" || true
  fi
  wait "$bpid" || true
  wait "$ppid" || true
  if [ -n "$spid" ]; then wait "$spid" || true; fi
}

for i in $(seq 1 "$RUNS"); do
  run "without-$i" without
  run "with-$i" with
done
run takeover kill
replay=$(realpath "$BUILD/bin/throng-replay")
"$replay" verify --jobs 2 "$out/takeover/standby.tlog" >"$out/takeover/verify-standby.txt" 2>&1 || true
"$replay" verify --jobs 2 "$out/takeover/primary.tlog" >"$out/takeover/verify-primary.txt" 2>&1 || true

python3 - "$out" "$RUNS" <<'PY'
import json, sys, os
out, runs = sys.argv[1], int(sys.argv[2])
def cpu(path):
    try:
        u, s = open(path).read().split()[-2:]
        return float(u) + float(s)
    except Exception:
        return float('nan')
def load(path):
    try:
        return json.load(open(path))
    except Exception:
        return {}
print("cost (CPU seconds over the match; tick ms p50/p99 of the primary)")
for mode in ("without", "with"):
    for i in range(1, runs + 1):
        d = f"{out}/{mode}-{i}"
        p = load(f"{d}/primary.json")
        t = p.get("tick_ms", {})
        line = f"  {mode:8s} run {i}: primary {cpu(d + '/primary.cpu'):6.2f} s, tick p50 {t.get('p50', float('nan')):.2f} p99 {t.get('p99', float('nan')):.2f} ms"
        if mode == "with":
            s = load(f"{d}/standby.json")
            line += (f"; standby {cpu(d + '/standby.cpu'):6.2f} s, followed {s.get('ticks_applied')} ticks, "
                     f"mismatches {s.get('mismatches')}, end {s.get('end_reason')}, same final hash "
                     f"{s.get('state_hash') == p.get('state_hash')}")
        print(line)
d = f"{out}/takeover"
b, s = load(f"{d}/bots.json"), load(f"{d}/standby.json")
ia = b.get("snapshot_interarrival_ms", {})
print("takeover (SIGKILL of the primary)")
print(f"  bots: joined {b.get('joined')}, rejoined {b.get('bots_rejoined')}, longest run of missed ticks {b.get('max_snapshot_gap_ticks')}, "
      f"missed ticks {b.get('snapshot_gap_ticks')}, snapshot interarrival p99 {ia.get('p99')} max {ia.get('max')} ms")
for line in open(f"{d}/standby.log"):
    if "taking over" in line or "took over" in line or "match ended" in line:
        print("  standby:", line.strip().split("] ", 2)[-1])
for who in ("standby", "primary"):
    lines = [l for l in open(f"{d}/verify-{who}.txt").read().splitlines() if l.startswith(("verified", "MISMATCH", "note", "LOG"))]
    print(f"  {who}'s log:", " / ".join(lines) if lines else "(no verdict)")
txt = open(f"{d}/standby.txt").read()
for line in txt.splitlines():
    if line.startswith(("clients", "commands", "ticks", "tick ms")):
        print("  new primary:", line)
PY
