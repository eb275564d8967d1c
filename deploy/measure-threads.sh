#!/usr/bin/env bash
# The solve on one and two threads (WorldSettings::threads): tick time and the state hash, which
# must not depend on the thread count. Runs alternate between 1 and 2 threads, REPS times each, and
# report the median of the runs' tick medians (this machine's speed drifts within minutes, and the
# second core is shared with whatever else the host runs). Prints a Markdown table and
# exits 1 if any scene's hash differs between thread counts; with
# JSON_OUT=FILE also writes the rows as JSON (deploy/make-benchmarks-doc.sh renders them).
#   deploy/measure-threads.sh [REPS=3] (BIN=build/release/bin/throng-bench, TICKS=200)
set -euo pipefail
bench=${BIN:-build/release/bin/throng-bench}
[[ -x $bench ]] || { echo "measure-threads: $bench not found (build Release first)" >&2; exit 2; }
reps=${1:-3}
[[ $reps =~ ^[1-9][0-9]*$ ]] || { echo "measure-threads: REPS must be a positive whole number, got '$reps'" >&2; exit 2; }
ticks=${TICKS:-200}
runs=("crush 20000" "crush 100000" "mixed 20000" "mixed 100000" "battle 20000")
out=$(mktemp); trap 'rm -f "$out"' EXIT
for run in "${runs[@]}"; do
  read -r scene n <<<"$run"
  for ((r = 1; r <= reps; ++r)); do
    for threads in 1 2; do
      echo "measure-threads: $scene $n, $threads thread(s), run $r of $reps" >&2
      "$bench" --scene "$scene" --agents "$n" --ticks "$ticks" --residual-from 0 --threads "$threads" --json |
        python3 -c "
import json, sys
j = json.load(sys.stdin); p = j['phase_median_us']
print('$scene', $n, $threads, j['tick_us']['median'], j['tick_us']['p95'], p['solve'], p['broadphase'], j['state_hash'])" >>"$out"
    done
  done
done
python3 - "$out" "${JSON_OUT:-}" "$reps" "$ticks" <<'PY'
import json, statistics, sys
rows = {}
for line in open(sys.argv[1]):
    scene, n, t, med, p95, solve, broad, h = line.split()
    rows.setdefault((scene, int(n)), {}).setdefault(int(t), []).append((float(med), float(p95), float(solve), float(broad), h))
print("| scene | N | 1 thread: median / p95 µs (solve) | 2 threads: median / p95 µs (solve) | speed-up (median) | same hash |")
print("|---|---|---|---|---|---|")
bad = False
summary = []
for (scene, n), by in rows.items():
    def med(t, k): return statistics.median(r[k] for r in by[t])
    hashes = {r[4] for t in by for r in by[t]}
    same = len(hashes) == 1
    bad |= not same
    summary.append({"scene": scene, "agents": n, "same_hash": same, "hashes": sorted(hashes),
                    "by_threads": {str(t): {"median_us": med(t, 0), "p95_us": med(t, 1), "solve_us": med(t, 2)} for t in by}})
    print("| %s | %d | %.0f / %.0f (%.0f) | %.0f / %.0f (%.0f) | %.2f× | %s |" % (
        scene, n, med(1, 0), med(1, 1), med(1, 2), med(2, 0), med(2, 1), med(2, 2), med(1, 0) / med(2, 0),
        "yes" if same else "NO: " + " ".join(sorted(hashes))))
if sys.argv[2]:
    with open(sys.argv[2], "w") as f:
        json.dump({"reps": int(sys.argv[3]), "ticks": int(sys.argv[4]), "rows": summary}, f, indent=1)
sys.exit(1 if bad else 0)
PY
