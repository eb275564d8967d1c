#!/usr/bin/env bash
# The README's first quick-start command: installs dependencies, builds the Release binaries and
# runs the main job on the built-in default scene. Until the match server lands this is the
# headless battle (`throng-bench --scene battle`), which prints a summary at the end.
# Extra arguments are passed to throng-bench (e.g. --ticks 1800 --json).
set -euo pipefail
cd "$(dirname "$0")/.."
bash deploy/install-deps.sh
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j "$(nproc)" --target throng-bench
exec build/release/bin/throng-bench --scene battle "$@"
