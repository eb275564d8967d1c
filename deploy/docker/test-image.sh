#!/usr/bin/env bash
# Runs a match in the image (host network) with 20 bots outside it, reads /healthz through the
# container's HEALTHCHECK and the admin port, and stops the container with SIGTERM (graceful).
#   deploy/docker/test-image.sh [TAG=throng-server:latest] [BIN_DIR=build/release/bin]
set -euo pipefail
tag=${1:-throng-server:latest}
bin=${2:-build/release/bin}
pm() { podman --runtime runc --cgroup-manager=cgroupfs "$@"; }
name=throng-image-test-$$
trap 'pm rm -f "$name" >/dev/null 2>&1 || true' EXIT
pm run -d --name "$name" --network host -e THRONG_LISTEN=tcp://0.0.0.0:7460 -e THRONG_ADMIN_PORT=9480 \
  -e THRONG_NPCS=1000 -e THRONG_LOG_FORMAT=json "$tag" >/dev/null
for _ in $(seq 1 50); do curl -fsS http://127.0.0.1:9480/healthz >/dev/null 2>&1 && break; sleep 0.2; done
echo "test-image: /healthz -> $(curl -fsS http://127.0.0.1:9480/healthz)"
"$bin/throng-bots" --server tcp://127.0.0.1:7460 --clients 20 --duration 10 --server-wait 30 --json /tmp/$name-bots.json -q
pm healthcheck run "$name" && echo "test-image: container HEALTHCHECK healthy" || { echo "test-image: HEALTHCHECK failed" >&2; exit 1; }
pm kill --signal TERM "$name" >/dev/null
pm wait "$name" >/dev/null || true
echo "test-image: exit code $(pm inspect -f '{{.State.ExitCode}}' "$name")"
pm logs "$name" 2>&1 | tail -3
python3 -c "
import json; b=json.load(open('/tmp/$name-bots.json'))
print('test-image: %d/20 bots joined, latency p50 %.1f ms p99 %.1f ms' % (b['joined'], b['latency_ms']['p50'], b['latency_ms']['p99']))
raise SystemExit(0 if b['joined'] == 20 else 1)"
