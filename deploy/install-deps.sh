#!/usr/bin/env bash
# Installs everything Throng needs to build and test, from Debian bookworm packages only.
# Idempotent: safe to run on every CI run and on a developer machine that already has them.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev        # linear algebra (FCL interop, validation references)
  libfcl-dev           # fixed scenery: BVH broadphase + distance/penetration vs capsules
  nlohmann-json3-dev   # scene, parameter-table and push-policy files
  libcli11-dev         # command-line parsing with --help for every binary
  libfmt-dev           # tables and reports
  libxxhash-dev        # 64-bit per-tick state hash (XXH3)
  libgtest-dev libgmock-dev  # unit/integration tests under ctest
  libbenchmark-dev     # micro benchmarks
  libfastrtps-dev libfastcdr-dev fastddsgen fastdds-tools  # eProsima Fast DDS 2.9: topics, IDL compiler, CLI
  libboost-dev         # Asio (fixed-tick loop, signals) and Beast (admin HTTP, viewer WebSocket)
  libspdlog-dev        # server/bot logs with levels and timestamps
  chromium             # headless browser for throng-view's end-to-end test (DevTools protocol)
  libzstd-dev          # match-log tick blocks compressed with zstd
  prometheus-cpp-dev   # /metrics: the metrics registry and its Prometheus text format (core library only)
  openssl              # throng-pki: DDS Security certificates and signed governance/permissions
  iproute2 python3     # the hosting test: a match over TCP across network namespaces (ip netns), its report
  curl                 # deploy/soak.sh reads the admin endpoint
  clang-14 libclang-rt-14-dev  # deploy/fuzz.sh: libFuzzer (libclang_rt.fuzzer) and clang's ASan/UBSan runtimes
)

if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; else SUDO=; fi
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
