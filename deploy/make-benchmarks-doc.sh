#!/usr/bin/env bash
# Regenerates docs/benchmarks.md and the engine rows of the README's figures table from
# throng-bench output: measures, keeps the raw results in server/bench/results/, renders.
#   deploy/make-benchmarks-doc.sh            measure everything (about 15 minutes here), then render
#   deploy/make-benchmarks-doc.sh --render   render from the results already in server/bench/results/
# BIN_DIR=build/release/bin (a Release build), REPS=3 (measure-threads.sh runs per thread count).
# Run it on a quiet machine: the tick times are wall-clock medians.
set -euo pipefail
cd "$(dirname "$0")/.."
bin_dir=${BIN_DIR:-build/release/bin}
results=server/bench/results
render_only=0
case "${1:-}" in
  "") ;;
  --render) render_only=1 ;;
  -h|--help) sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) echo "make-benchmarks-doc: unknown argument '$1' (--render or nothing; --help)" >&2; exit 2 ;;
esac

if ((!render_only)); then
  [[ -x $bin_dir/throng-bench ]] || { echo "make-benchmarks-doc: $bin_dir/throng-bench not found (build Release first)" >&2; exit 2; }
  mkdir -p "$results"
  python3 - "$results/machine.json" <<'PY'
import datetime, json, os, platform, subprocess, sys
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), platform.machine())
commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
json.dump({"cpu": cpu, "cores": os.cpu_count(), "date": datetime.date.today().isoformat(), "commit": commit},
          open(sys.argv[1], "w"), indent=1)
PY
  echo "=== make-benchmarks-doc: sweep (K and N on crush, one_cell)" >&2
  sweep_dir=$(mktemp -d); trap 'rm -rf "$sweep_dir"' EXIT
  "$bin_dir/throng-bench" sweep --out "$sweep_dir" >"$results/crush-sweep.txt"
  cp "$sweep_dir/sweep.json" "$results/crush-sweep.json"
  cp "$sweep_dir/sweep.svg" "$results/crush-sweep.svg"
  echo "=== make-benchmarks-doc: contact validation" >&2
  "$bin_dir/throng-bench" validate-contacts --pairs 100000 >"$results/contact-validation.txt"
  echo "=== make-benchmarks-doc: threads" >&2
  BIN="$bin_dir/throng-bench" JSON_OUT="$results/threads.json" bash deploy/measure-threads.sh "${REPS:-3}" >/dev/null
  echo "=== make-benchmarks-doc: worst tick" >&2
  BIN="$bin_dir/throng-bench" JSON_OUT="$results/worst-tick.json" bash deploy/measure-worst-tick.sh 5000 20000 >/dev/null
fi
python3 deploy/render_benchmarks.py "$results" docs/benchmarks.md README.md
echo "make-benchmarks-doc: wrote docs/benchmarks.md and the README's engine figures from $results" >&2
