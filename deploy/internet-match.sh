#!/usr/bin/env bash
# A match played across an emulated internet path: the server in one network namespace, bot
# processes in another behind a home NAT, joined by throng-link (delay, jitter, loss). Each bot
# process is one player's machine with its own connection. Prints one line of figures and, with
# OUT_JSON set, writes them; exits non-zero when a bot did not join or play, the server did not
# exit cleanly, or the stream fell behind the match.
#
#   deploy/internet-match.sh [SCHEME=udp] [BOTS=10] [SECONDS=10] [PROCESSES=2] [BIN_DIR=build/release/bin] \
#       [-- throng-link options, default: --rtt-ms 100 --jitter-ms 5 --loss 0.01]
# SCHEME: udp (the NAT-crossing UDP path) or tcp. Root only (ip netns); exits 77 elsewhere.
set -euo pipefail
scheme=${1:-udp}
bots=${2:-10}
seconds=${3:-10}
procs=${4:-2}
bin=${5:-build/release/bin}
shift $(( $# < 5 ? $# : 5 ))
[[ ${1:-} == -- ]] && shift
link_args=("$@")
[[ ${#link_args[@]} -gt 0 ]] || link_args=(--rtt-ms 100 --jitter-ms 5 --loss 0.01)
die() { echo "internet-match: $*" >&2; exit 2; }
[[ $scheme == udp || $scheme == tcp ]] || die "SCHEME must be udp or tcp, got '$scheme'"
[[ $bots =~ ^[0-9]+$ && $bots -ge 1 && $bots -le 200 ]] || die "BOTS must be 1..200, got '$bots'"
[[ $seconds =~ ^[0-9]+$ && $seconds -ge 2 && $seconds -le 3600 ]] || die "SECONDS must be 2..3600, got '$seconds'"
[[ $procs =~ ^[0-9]+$ && $procs -ge 1 && $procs -le $bots ]] || die "PROCESSES must be 1..BOTS, got '$procs'"
for b in throng-server throng-bots throng-link; do [[ -x $bin/$b ]] || die "$bin/$b not found (build first)"; done
if [[ $(id -u) -ne 0 ]] || ! command -v ip >/dev/null; then
  echo "internet-match: needs root and iproute2 (ip netns); skipped" >&2
  exit 77
fi
bin=$(cd "$bin" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=lib/emulated-link.sh
source "$here/lib/emulated-link.sh"

out=$(mktemp -d /tmp/throng-internet.XXXXXX)
server_pid=""
bot_pids=()
cleanup() {
  [[ -n $server_pid ]] && kill "$server_pid" 2>/dev/null || true
  for p in "${bot_pids[@]}"; do kill "$p" 2>/dev/null || true; done
  link_down
}
trap cleanup EXIT
link_up "$$" "$bin" "${link_args[@]}"

port=7400
listen="$scheme://$LINK_SERVER_ADDR:$port"
ip netns exec "$LINK_SRV" "$bin/throng-server" --listen "$listen" --public-address "$LINK_SERVER_ADDR" \
  --npcs 1000 --no-log --admin-port -1 --duration $((seconds + 60)) --summary-json "$out/server.json" \
  >"$out/server.txt" 2>&1 &
server_pid=$!
for _ in $(seq 1 300); do
  grep -q "listening on $scheme://" "$out/server.txt" 2>/dev/null && break
  kill -0 "$server_pid" 2>/dev/null || break
  sleep 0.1
done
grep -q "listening on $scheme://" "$out/server.txt" || { echo "internet-match: the server did not start" >&2; tail -20 "$out/server.txt" >&2; exit 1; }

echo "internet-match: $bots bots in $procs processes behind the NAT, $listen, link: ${link_args[*]}, $seconds s"
for ((p = 0; p < procs; ++p)); do
  n=$(( bots / procs + (p < bots % procs ? 1 : 0) ))
  ip netns exec "$LINK_CLI" "$bin/throng-bots" --server "$listen" --clients "$n" --duration "$seconds" \
    --behavior mix --server-wait 30 --json "$out/bots-$p.json" -q >"$out/bots-$p.txt" 2>&1 &
  bot_pids+=($!)
done
failed=0
for ((p = 0; p < procs; ++p)); do
  if ! wait "${bot_pids[$p]}"; then
    echo "internet-match: bot process $p failed:" >&2
    tail -20 "$out/bots-$p.txt" >&2
    failed=1
  fi
done
bot_pids=()
kill -TERM "$server_pid"
if ! wait "$server_pid"; then
  echo "internet-match: the server did not exit 0" >&2
  tail -20 "$out/server.txt" >&2
  failed=1
fi
server_pid=""
link_down
[[ $failed -eq 0 ]] || exit 1

python3 "$here/internet_match_report.py" "$out" "$bots" "$procs" "$scheme" "$LINK_JSON" "${OUT_JSON:-}" "${link_args[*]}"
