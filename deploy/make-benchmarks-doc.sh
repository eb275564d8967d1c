#!/usr/bin/env bash
# Regenerates docs/benchmarks.md and the engine rows of the README's figures table from
# throng-bench output: measures, keeps the raw results in server/bench/results/, renders.
#   deploy/make-benchmarks-doc.sh            measure everything (about 5 minutes here), then render
#   deploy/make-benchmarks-doc.sh --render   render from the results already in server/bench/results/
# BIN_DIR=build/release/bin (a Release build), REPS=3 (measure-threads.sh runs per thread count).
# Run it on a quiet machine: the tick times are wall-clock medians.
set -euo pipefail
self=$(realpath "$0")
# A BIN_DIR given is taken from where the script was called; the default is the repository's.
[[ -n ${BIN_DIR:-} ]] && bin_dir=$(realpath -m "$BIN_DIR")
cd "$(dirname "$self")/.."
bin_dir=${bin_dir:-build/release/bin}
results=server/bench/results
render_only=0
case "${1:-}" in
  "") ;;
  --render) render_only=1 ;;
  -h|--help) sed -n '2,7p' "$self" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) echo "make-benchmarks-doc: unknown argument '$1' (--render or nothing; --help)" >&2; exit 2 ;;
esac

threads_status=0
if ((!render_only)); then
  [[ -x $bin_dir/throng-bench ]] || { echo "make-benchmarks-doc: $bin_dir/throng-bench not found (build Release first)" >&2; exit 2; }
  # Measured into a scratch folder and moved into $results only when every run finished, so a
  # failed run never leaves new figures beside old ones.
  new=$(mktemp -d); trap 'rm -rf "$new"' EXIT
  echo "=== make-benchmarks-doc: sweep (K and N on crush, one_cell)" >&2
  "$bin_dir/throng-bench" sweep --out "$new/sweep" >"$new/crush-sweep.txt"
  mv "$new/sweep/sweep.json" "$new/crush-sweep.json"
  mv "$new/sweep/sweep.svg" "$new/crush-sweep.svg"
  rmdir "$new/sweep"
  echo "=== make-benchmarks-doc: contact validation" >&2
  "$bin_dir/throng-bench" validate-contacts --pairs 100000 >"$new/contact-validation.txt"
  echo "=== make-benchmarks-doc: threads" >&2
  # A state hash that differs between thread counts is a failure, reported after the render (its
  # table says which scene) rather than stopping the other measurements.
  BIN="$bin_dir/throng-bench" JSON_OUT="$new/threads.json" bash deploy/measure-threads.sh "${REPS:-3}" >&2 || threads_status=$?
  [[ -f $new/threads.json ]] || { echo "make-benchmarks-doc: measure-threads.sh failed (exit $threads_status)" >&2; exit 1; }
  echo "=== make-benchmarks-doc: worst tick" >&2
  BIN="$bin_dir/throng-bench" JSON_OUT="$new/worst-tick.json" bash deploy/measure-worst-tick.sh 5000 20000 >&2
  python3 - "$new/machine.json" <<'PY'
import datetime, json, os, platform, subprocess, sys
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), platform.machine())
try:
    commit = subprocess.run(["git", "describe", "--always", "--dirty"], capture_output=True, text=True).stdout.strip()
except OSError:
    commit = ""
json.dump({"cpu": cpu, "cores": os.cpu_count(), "date": datetime.date.today().isoformat(), "commit": commit or "unknown"},
          open(sys.argv[1], "w"), indent=1)
PY
  mkdir -p "$results"
  mv "$new"/* "$results/"
fi
python3 deploy/render_benchmarks.py "$results" docs/benchmarks.md README.md
echo "make-benchmarks-doc: wrote docs/benchmarks.md and the README's engine figures from $results" >&2
if ((threads_status != 0)); then
  echo "make-benchmarks-doc: the state hash differed between thread counts (see the threads table)" >&2
  exit 1
fi
