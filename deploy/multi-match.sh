#!/usr/bin/env bash
# Several matches on one host at once, each a throng-server with its own bots, over TCP: each
# match has its own listening port (7500 + k), which is what keeps them apart (they share DDS
# domain 0; a TCP-only participant discovers only the peers it connects to). On Agones every
# GameServer gets its own port (portPolicy Passthrough) and its own pod network, so nothing has to
# be chosen by hand there. Prints per-match tick p99, latency p50/p99 and bytes per client.
#
#   deploy/multi-match.sh [MATCHES=4] [BOTS=10] [SECONDS=20] [NPCS=500] [BIN_DIR=build/release/bin]
set -euo pipefail
matches=${1:-4} bots=${2:-10} seconds=${3:-20} npcs=${4:-500} bin=${5:-build/release/bin}
for v in "$matches" "$bots" "$seconds" "$npcs"; do
  [[ $v =~ ^[0-9]+$ && $v -ge 1 ]] || { echo "multi-match: arguments must be positive integers (got '$v')" >&2; exit 2; }
done
(( matches <= 16 )) || { echo "multi-match: at most 16 matches" >&2; exit 2; }
for b in throng-server throng-bots; do [[ -x $bin/$b ]] || { echo "multi-match: $bin/$b not found (build first)" >&2; exit 2; }; done
out=$(mktemp -d /tmp/throng-multi.XXXXXX)
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT

for ((k = 0; k < matches; k++)); do
  "$bin/throng-server" --listen "tcp://0.0.0.0:$((7500 + k))" --npcs "$npcs" --no-log --admin-port 0 \
    --duration $((seconds + 30)) --summary-json "$out/server-$k.json" >"$out/server-$k.txt" 2>"$out/server-$k.log" &
  pids+=($!)
done
echo "multi-match: $matches servers on tcp ports 7500..$((7500 + matches - 1)), $bots bots each, ${seconds} s"
bot_pids=()
for ((k = 0; k < matches; k++)); do
  "$bin/throng-bots" --server "tcp://127.0.0.1:$((7500 + k))" --clients "$bots" --duration "$seconds" --server-wait 20 \
    --name-prefix "m$k" --json "$out/bots-$k.json" -q >"$out/bots-$k.txt" 2>&1 &
  bot_pids+=($!)
done
failed=0
for p in "${bot_pids[@]}"; do wait "$p" || failed=1; done
for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
for p in "${pids[@]}"; do wait "$p" || failed=1; done
pids=()
python3 - "$out" "$matches" "$bots" <<'PY'
import json, sys
out, matches, want = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
ok = True
for k in range(matches):
    s = json.load(open(f"{out}/server-{k}.json"))
    b = json.load(open(f"{out}/bots-{k}.json"))
    names = {c["name"] for c in s["clients"]}
    foreign = [n for n in names if not n.startswith(f"m{k}-")]
    per = b["per_client"]
    mb = sum(c["snapshots"]["bytes"] for c in per) / max(1, len(per)) / 1e6
    print(f"match {k}: {b['joined']}/{want} joined, tick p99 {s['tick_ms']['p99']:.2f} ms (overruns {s['overruns']}), "
          f"latency p50 {b['latency_ms']['p50']:.1f} ms p99 {b['latency_ms']['p99']:.1f} ms, {mb:.2f} MB per client, "
          f"clients of other matches seen: {len(foreign)}")
    ok = ok and b["joined"] == want and len(names) == want and not foreign
sys.exit(0 if ok else 1)
PY
status=$?
[[ $failed -eq 0 && $status -eq 0 ]] || { echo "multi-match: FAILED (logs in $out)" >&2; exit 1; }
echo "multi-match: ok (logs in $out)"
