#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz, THRONG_FUZZ=ON, clang-14) in build/fuzz and runs each
# for SECONDS_PER_TARGET seconds on a scratch copy of its seed corpus (the committed corpus never
# grows). One line per target: executions, coverage (cov / ft from libFuzzer's final stats) and
# crashes; the inputs that crashed are kept in build/fuzz/crashes/<target>/. Exits 1 if any crashed.
#   deploy/fuzz.sh [SECONDS_PER_TARGET]   (default 60)
#   FUZZ_TARGETS="snapshot matchlog" deploy/fuzz.sh 300   (a subset)
#   JOBS=2 (build parallelism; default: nproc)
set -euo pipefail
cd "$(dirname "$0")/.."

SECONDS_PER_TARGET=${1:-60}
BUILD=build/fuzz
JOBS=${JOBS:-$(nproc)}
CORPUS=tests/fuzz/corpus
ALL_TARGETS=$(cd tests/fuzz && ls -1 *.cpp | sed 's/\.cpp$//' | grep -v '^corpus_gen$')
TARGETS=${FUZZ_TARGETS:-$ALL_TARGETS}

echo "=== fuzz: build $BUILD"
if [ ! -f "$BUILD/build.ninja" ]; then
  CC=clang-14 CXX=clang++-14 cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Fuzz -DTHRONG_FUZZ=ON >/dev/null
fi
if ! cmake --build "$BUILD" -j "$JOBS" --target throng_fuzz_all >"$BUILD/build.log" 2>&1; then
  grep -E -A5 'error|FAILED' "$BUILD/build.log" | head -40
  echo "fuzz: build failed ($BUILD/build.log)"
  exit 1
fi

WORK=$(mktemp -d "${TMPDIR:-/tmp}/throng_fuzz.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
# Leaks are reported (an input that leaks is a finding); the targets keep their fixtures in
# function-local statics on purpose, which LSan does not count.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

failed=0
printf '%-18s %12s %8s %8s %8s\n' target execs cov ft crashes
for t in $TARGETS; do
  bin="$BUILD/bin/fuzz_$t"
  [ -x "$bin" ] || { echo "fuzz: no $bin"; exit 1; }
  mkdir -p "$WORK/$t/corpus" "$BUILD/crashes/$t"
  [ -d "$CORPUS/$t" ] && cp "$CORPUS/$t"/* "$WORK/$t/corpus/" 2>/dev/null || true
  log="$WORK/$t/log"
  # -timeout: one input taking longer than 30 s is a hang (a crash); -rss_limit_mb: a memory blow-up.
  set +e
  "$bin" "$WORK/$t/corpus" -max_total_time="$SECONDS_PER_TARGET" -print_final_stats=1 -timeout=30 \
    -rss_limit_mb=2048 -artifact_prefix="$BUILD/crashes/$t/" >"$log" 2>&1
  rc=$?
  # A timeout is re-run alone: on a machine shared with other builds a process can stall for
  # seconds. One that finishes well within the limit alone is reported, not counted as a crash.
  if [ "$rc" -ne 0 ] && grep -q 'ERROR: libFuzzer: timeout' "$log"; then
    unit=$(sed -n 's/.*Test unit written to //p' "$log" | tail -1)
    if [ -n "$unit" ] && timeout 60 "$bin" -timeout=10 "$unit" >"$log.rerun" 2>&1; then
      echo "    $t: a timeout that does not reproduce alone ($unit): machine load, not counted"
      rc=0
    fi
  fi
  set -e
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  cov=$(grep -oE 'cov: [0-9]+' "$log" | tail -1 | cut -d' ' -f2)
  ft=$(grep -oE 'ft: [0-9]+' "$log" | tail -1 | cut -d' ' -f2)
  crashes=0
  if [ "$rc" -ne 0 ]; then
    crashes=1
    failed=1
    cp "$log" "$BUILD/crashes/$t/last.log"
  fi
  printf '%-18s %12s %8s %8s %8s\n' "$t" "${execs:-?}" "${cov:-?}" "${ft:-?}" "$crashes"
  if [ "$rc" -ne 0 ]; then
    grep -m1 -E 'ERROR: |runtime error|deadly signal|Timeout|out-of-memory' "$log" | sed 's/^/    /' || true
    echo "    log: $BUILD/crashes/$t/last.log; inputs: $BUILD/crashes/$t/"
  fi
done
[ "$failed" -eq 0 ] && echo "=== fuzz: no crashes" || echo "=== fuzz: CRASHES (see above)"
exit "$failed"
