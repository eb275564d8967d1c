#!/usr/bin/env bash
# A match reached over TCP across two network namespaces, the way a cloud-hosted match is reached:
# the server listens with --listen tcp://ADDR:PORT in one namespace, the bots connect with
# --server tcp://ADDR:PORT from another, over a veth pair with no multicast route and no shared
# memory between them. Prints the bots' latency and bytes per client; exits non-zero when a bot
# did not join or play. Needs root (ip netns); CI runs as root.
#
#   deploy/netns-match.sh [BOTS=20] [SECONDS=20] [BIN_DIR=build/release/bin]
set -euo pipefail
bots=${1:-20}
seconds=${2:-20}
bin=${3:-build/release/bin}
[[ $bots =~ ^[0-9]+$ && $bots -ge 1 && $bots -le 200 ]] || { echo "netns-match: BOTS must be 1..200, got '$bots'" >&2; exit 2; }
[[ $seconds =~ ^[0-9]+$ && $seconds -ge 2 && $seconds -le 3600 ]] || { echo "netns-match: SECONDS must be 2..3600, got '$seconds'" >&2; exit 2; }
for b in throng-server throng-bots; do [[ -x $bin/$b ]] || { echo "netns-match: $bin/$b not found (build first)" >&2; exit 2; }; done
if [[ $(id -u) -ne 0 ]] || ! command -v ip >/dev/null; then
  echo "netns-match: needs root and iproute2 (ip netns); skipped" >&2
  exit 77
fi
bin=$(cd "$bin" && pwd)

tag=$$
srv=throng_srv_$tag cli=throng_cli_$tag
out=$(mktemp -d /tmp/throng-netns.XXXXXX)
server_pid=""
cleanup() {
  [[ -n $server_pid ]] && kill "$server_pid" 2>/dev/null || true
  ip netns del "$srv" 2>/dev/null || true
  ip netns del "$cli" 2>/dev/null || true
}
trap cleanup EXIT

ip netns add "$srv"
ip netns add "$cli"
ip link add "ths$tag" type veth peer name "thc$tag"
ip link set "ths$tag" netns "$srv"
ip link set "thc$tag" netns "$cli"
ip -n "$srv" addr add 10.201.0.1/24 dev "ths$tag"
ip -n "$cli" addr add 10.201.0.2/24 dev "thc$tag"
for ns in "$srv" "$cli"; do ip -n "$ns" link set lo up; done
ip -n "$srv" link set "ths$tag" up
ip -n "$cli" link set "thc$tag" up

# No multicast route: discovery cannot fall back to it.
if ip netns exec "$cli" ip route get 239.255.0.1 >/dev/null 2>&1; then
  echo "netns-match: the client namespace has a multicast route; the test would prove nothing" >&2
  exit 1
fi

port=7400
ip netns exec "$srv" "$bin/throng-server" --listen "tcp://10.201.0.1:$port" --public-address 10.201.0.1 \
  --npcs 1000 --no-log --admin-port -1 --duration $((seconds + 30)) --summary-json "$out/server.json" \
  >"$out/server.txt" 2>&1 &
server_pid=$!

# Players connect once the server is up, as in a fleet (Agones hands out a server's address only
# once it is Ready): the server logs its listener after its DDS endpoints exist.
for _ in $(seq 1 300); do
  grep -q "listening on tcp://" "$out/server.txt" 2>/dev/null && break
  kill -0 "$server_pid" 2>/dev/null || break
  sleep 0.1
done
grep -q "listening on tcp://" "$out/server.txt" || { echo "netns-match: the server did not start" >&2; tail -20 "$out/server.txt" >&2; exit 1; }

echo "netns-match: server in $srv listening on tcp://10.201.0.1:$port; $bots bots in $cli for $seconds s"
if ! ip netns exec "$cli" "$bin/throng-bots" --server "tcp://10.201.0.1:$port" --clients "$bots" --duration "$seconds" \
  --server-wait 20 --json "$out/bots.json" -q >"$out/bots.txt" 2>&1; then
  echo "netns-match: throng-bots failed:" >&2
  tail -20 "$out/bots.txt" >&2
  tail -20 "$out/server.txt" >&2
  # The TCP connections as they stand (a stalled discovery: was the bots' connection up?).
  for ns in "$srv" "$cli"; do echo "netns-match: TCP in $ns:" >&2; ip netns exec "$ns" ss -tni >&2 || true; done
  exit 1
fi
kill -TERM "$server_pid"
wait "$server_pid" || { echo "netns-match: the server did not exit 0" >&2; tail -20 "$out/server.txt" >&2; exit 1; }
server_pid=""

python3 - "$out/bots.json" "$out/server.json" "$bots" <<'PY'
import json, sys
bots, server, want = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), int(sys.argv[3])
lat = bots["latency_ms"]
per = bots["per_client"]
mean_bytes = sum(c["snapshots"]["bytes"] for c in per) / max(1, len(per))
mean_kbps = sum(c["kbit_per_s"] for c in per) / max(1, len(per))
print(f"netns-match: {bots['joined']}/{want} joined, {bots['join_failed']} failed; latency p50 {lat['p50']:.1f} ms "
      f"p99 {lat['p99']:.1f} ms ({bots['tick_hz']} Hz); snapshots {mean_kbps:.0f} kbit/s, {mean_bytes / 1e6:.2f} MB "
      f"per client over {bots['duration_s']:.0f} s; longest snapshot gap {bots['snapshot_gap_ticks']} ticks; "
      f"the server saw {len(server['clients'])} clients")
ok = bots["joined"] == want and bots["join_failed"] == 0 and len(server["clients"]) == want
ok = ok and all(c["snapshots"]["received"] > 0 and c["commands"]["applied"] > 0 for c in per)
sys.exit(0 if ok else 1)
PY
