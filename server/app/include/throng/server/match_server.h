#pragma once
// throng-server's whole job: one Match (server/match) driven by a fixed-tick Asio loop, its inputs
// fed by the DDS transport, its outputs published back, metrics on the admin endpoint.
//
// Threads: run() is the tick thread (an io_context with the tick timer and the signal set); Fast
// DDS listener threads only push into the match's input queue; the admin HTTP server has its own
// thread and reads atomics. The world is only ever touched by the tick thread.
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include <vector>

#include "throng/matchlog/log_header.h"
#include "throng/matchlog/writer.h"
#include "throng/protocol/dds_transport.h"
#include "throng/server/server_options.h"

namespace throng::server {

// run()'s exit code when another server took the match over (a higher epoch's PrimaryClaim).
inline constexpr int kExitFenced = 5;

// The DDS options of a match server (primary or standby): domain, transports, the server identity.
protocol::TransportOptions transport_options(const ServerOptions& options);

class MatchServer {
 public:
  // Builds the scene, the match, the DDS participant and the admin endpoint. Throws
  // std::exception with a message naming what failed (scene file, DDS domain, admin port).
  explicit MatchServer(const ServerOptions& options);

  // A hot standby's takeover (standby_server.h): the match another server hosted, as the standby
  // followed it. The new server continues from the next tick with the same match id, clients,
  // entities and command sequences; clients keep playing without rejoining.
  struct Takeover {
    matchlog::LogHeader header;            // the primary's match: scene, config, match id
    std::vector<std::uint8_t> checkpoint;  // after the last followed tick, with snapshot baselines
    std::uint64_t epoch = 2;               // the highest epoch the standby saw + 1
    std::uint64_t server_id = 0;           // the standby's (PrimaryClaim::server_id); 0: draw one
    // Created when the standby started, so that clients discovered it long before it publishes.
    std::unique_ptr<protocol::ServerTransport> transport;
    // The standby's match log (it continues there), or null.
    std::unique_ptr<matchlog::MatchLogWriter> log;
  };
  MatchServer(const ServerOptions& options, Takeover&& takeover);
  ~MatchServer();
  MatchServer(const MatchServer&) = delete;
  MatchServer& operator=(const MatchServer&) = delete;

  // Hosts the match until --duration passes, request_stop() is called, or SIGINT/SIGTERM arrives
  // (when handle_signals). Shutdown is graceful: joins are refused, the current tick finishes,
  // the final match info says "ended", the summary is written. Returns the process exit code: 0,
  // or kExitFenced when a claim of a higher epoch for this match showed that a standby took it
  // over (then no further tick runs and no "ended" goes out).
  int run(bool handle_signals = true);

  // Thread-safe: the tick loop stops at its next tick.
  void request_stop();

  // The admin HTTP port actually bound (useful with --admin-port 0); 0 when disabled.
  std::uint16_t admin_port() const;

  // Thread-safe: what the DDS transport counted so far (samples, bytes, refused participants).
  protocol::TransportCounters transport_counters() const;

  // End-of-match figures (also written to --summary-json): ticks, overruns, tick time
  // percentiles, commands by reason, per-client counts, bytes, state hash.
  nlohmann::json summary() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace throng::server
