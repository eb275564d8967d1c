#!/usr/bin/env bash
# The image's entry point: throng-server with its flags taken from the environment (what
# container platforms set), then any arguments given to the container.
#   THRONG_LISTEN          --listen (tcp://ADDR:PORT or agones)     THRONG_PUBLIC_ADDRESS --public-address
#   THRONG_SCENE           --scene                                 THRONG_NPCS           --npcs
#   THRONG_TICK_HZ         --tick-hz                               THRONG_MAX_CLIENTS    --max-clients
#   THRONG_END_WHEN_EMPTY  --end-when-empty                        THRONG_DURATION       --duration
#   THRONG_ADMIN_PORT      --admin-port (bound on 0.0.0.0)         THRONG_LOG_DIR        --log-dir
#   THRONG_LOG_FORMAT      --log-format                            THRONG_LOG_LEVEL      --log-level
#   THRONG_SECURITY        --security (a mounted throng-pki directory)
set -euo pipefail
args=(--admin-bind 0.0.0.0)
add() { [[ -n ${2:-} ]] && args+=("$1" "$2"); return 0; }
add --listen "${THRONG_LISTEN:-}"
add --public-address "${THRONG_PUBLIC_ADDRESS:-}"
add --scene "${THRONG_SCENE:-}"
add --npcs "${THRONG_NPCS:-}"
add --tick-hz "${THRONG_TICK_HZ:-}"
add --max-clients "${THRONG_MAX_CLIENTS:-}"
add --end-when-empty "${THRONG_END_WHEN_EMPTY:-}"
add --duration "${THRONG_DURATION:-}"
add --admin-port "${THRONG_ADMIN_PORT:-}"
add --log-dir "${THRONG_LOG_DIR:-}"
add --log-format "${THRONG_LOG_FORMAT:-}"
add --log-level "${THRONG_LOG_LEVEL:-}"
add --security "${THRONG_SECURITY:-}"
exec /usr/local/bin/throng-server "${args[@]}" "$@"
