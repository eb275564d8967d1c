#!/usr/bin/env bash
# Players across an emulated internet path (throng-link, clients behind a home NAT): TCP against
# the UDP path, at 40, 100 and 200 ms round trip with +-5 ms jitter and 0, 1 and 3 % random loss,
# plus 2 % loss at 100 and 200 ms and one bursty case. 20 bots in 4 processes (players each have
# their own connection), SECONDS per cell. Keeps one JSON per cell in server/bench/results/internet/
# (render them into docs/benchmarks.md with deploy/make-benchmarks-doc.sh --render).
#   deploy/measure-internet.sh [SECONDS=10] [BIN_DIR=build/release/bin]
# Root only (ip netns). About 25 s a cell, 26 cells.
set -uo pipefail
seconds=${1:-10}
bin=${2:-build/release/bin}
cd "$(dirname "$0")/.."
out=server/bench/results/internet
new=$(mktemp -d)
trap 'rm -rf "$new"' EXIT
cells=()
for rtt in 40 100 200; do for loss in 0 0.01 0.03; do cells+=("rtt${rtt}-loss${loss}|--rtt-ms $rtt --jitter-ms 5 --loss $loss"); done; done
cells+=("rtt100-loss0.02|--rtt-ms 100 --jitter-ms 5 --loss 0.02" "rtt200-loss0.02|--rtt-ms 200 --jitter-ms 5 --loss 0.02")
# Gilbert-Elliott: bad 1 % of packets' chance to start, mean burst 4 packets, all lost in a burst
# (about 3.8 % lost in all, in runs).
cells+=("rtt100-burst|--rtt-ms 100 --jitter-ms 5 --burst 0.01,0.25")
status=0
for scheme in udp tcp; do
  for cell in "${cells[@]}"; do
    name=${cell%%|*} args=${cell#*|}
    echo "=== measure-internet: $scheme $name ($args)" >&2
    # shellcheck disable=SC2086
    OUT_JSON="$new/$scheme-$name.json" bash deploy/internet-match.sh "$scheme" 20 "$seconds" 4 "$bin" -- $args --seed 1
    rc=$?
    # 3: every bot played but the stream fell behind: a verdict the table shows, not a failed run.
    if [[ $rc -ne 0 && $rc -ne 3 ]]; then
      echo "measure-internet: $scheme $name failed (exit $rc; its figures, if any, are kept)" >&2
      status=1
    fi
  done
done
mkdir -p "$out"
rm -f "$out"/*.json
cp "$new"/*.json "$out"/ 2>/dev/null || true
echo "measure-internet: $(ls "$out" | wc -l) cells in $out" >&2
exit $status
