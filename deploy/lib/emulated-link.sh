# Sourced by the scripts that put a server and its clients on either side of an emulated internet
# path (throng-link): two network namespaces joined by TUN devices, the clients behind a home NAT.
#   link_up TAG BIN_DIR [throng-link options...]   sets LINK_SRV, LINK_CLI (namespace names),
#                                                   LINK_PID, LINK_OUT (its stdout) and LINK_JSON
#   link_down                                       stops the link (it writes LINK_JSON) and
#                                                   removes the namespaces
# Addresses (throng-link's defaults): the server at 10.77.0.1 in LINK_SRV; the clients at
# 10.77.1.2 in LINK_CLI, seen by the server as 10.77.0.100.
LINK_SERVER_ADDR=10.77.0.1
LINK_NAT_ADDR=10.77.0.100
LINK_CLIENT_ADDR=10.77.1.2

link_up() {
  local tag=$1 bin=$2; shift 2
  LINK_SRV=thl_srv_$tag LINK_CLI=thl_cli_$tag
  LINK_OUT=$(mktemp /tmp/throng-link.XXXXXX.out)
  LINK_JSON=${LINK_OUT%.out}.json
  ip netns add "$LINK_SRV"
  ip netns add "$LINK_CLI"
  "$bin/throng-link" --server-ns "$LINK_SRV" --client-ns "$LINK_CLI" --json "$LINK_JSON" "$@" >"$LINK_OUT" 2>&1 &
  LINK_PID=$!
  local i
  for i in $(seq 1 50); do
    grep -q "^throng-link: up" "$LINK_OUT" 2>/dev/null && return 0
    kill -0 "$LINK_PID" 2>/dev/null || break
    sleep 0.1
  done
  echo "emulated-link: throng-link did not come up:" >&2
  cat "$LINK_OUT" >&2
  return 1
}

link_down() {
  if [[ -n ${LINK_PID:-} ]]; then
    kill -TERM "$LINK_PID" 2>/dev/null || true
    wait "$LINK_PID" 2>/dev/null || true
    LINK_PID=""
  fi
  [[ -n ${LINK_SRV:-} ]] && ip netns del "$LINK_SRV" 2>/dev/null || true
  [[ -n ${LINK_CLI:-} ]] && ip netns del "$LINK_CLI" 2>/dev/null || true
}
