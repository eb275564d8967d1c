#pragma once
// The Agones game-server lifecycle over Agones's REST SDK (the sidecar on 127.0.0.1, port from
// AGONES_SDK_HTTP_PORT; Debian has no package of Agones's C++ gRPC SDK). One thread, which never
// touches the match: it reads a few atomics the tick thread keeps (AgonesProbe) and
//   - POST /ready once the first tick ran (the transport is up by then),
//   - POST /health every health interval, but only when the tick loop completed a tick since the
//     previous ping: a stuck tick withholds the pings and Agones marks the server Unhealthy,
//   - PUT /metadata/label {"key": "players", "value": "N"} whenever the player count changes,
//   - POST /shutdown once the match has ended (log flushed, "ended" published).
// The sidecar may start after the server: every call is retried until it answers (the first
// failure is logged, and the first success after failures).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

namespace throng::server {

// Written by the tick thread, read by the SDK thread.
struct AgonesProbe {
  std::atomic<std::uint64_t> ticks{0};    // ticks completed
  std::atomic<std::uint32_t> players{0};  // clients connected now
  std::atomic<bool> ended{false};         // the match ended (after the last tick's publish)
};

struct AgonesOptions {
  std::uint16_t port = 9358;  // the sidecar's HTTP port (AGONES_SDK_HTTP_PORT)
  std::chrono::milliseconds health_interval{2000};
  std::chrono::milliseconds retry_interval{500};
  std::chrono::milliseconds request_timeout{2000};
  std::string player_label = "players";
};

// Where Agones says players reach this game server: the node's address and the port allocated
// to the GameServer's port named `port_name` (GET /gameserver, status.address and status.ports).
// With portPolicy Passthrough the container listens on that same port. Retries until the sidecar
// answers with both, or throws std::runtime_error after `timeout`.
struct AgonesEndpoint {
  std::string address;
  std::uint16_t port = 0;
};
AgonesEndpoint agones_endpoint(std::uint16_t sdk_port, const std::string& port_name, std::chrono::milliseconds timeout);

// The port from AGONES_SDK_HTTP_PORT, or 0 when it is not set. Throws std::invalid_argument when
// it is set but not a port number.
std::uint16_t agones_port_from_environment();

class AgonesSdk {
 public:
  AgonesSdk(const AgonesOptions& options, const AgonesProbe& probe);
  ~AgonesSdk();  // stops the thread (after the shutdown call if the match ended)
  AgonesSdk(const AgonesSdk&) = delete;
  AgonesSdk& operator=(const AgonesSdk&) = delete;

  // Blocks until POST /shutdown was answered or `timeout` passed (the match has ended: the process
  // is about to exit). Returns whether the sidecar acknowledged it.
  bool wait_shutdown_sent(std::chrono::milliseconds timeout);

  // Counters for the summary, tests and metrics.
  std::uint64_t health_pings() const;
  std::uint64_t health_withheld() const;  // intervals without a completed tick
  bool ready_sent() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace throng::server
