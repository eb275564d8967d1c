#pragma once
// throng-server --standby: a hot standby of the match on its DDS domain (docs/design/standby.md).
// It asks the primary for the match (its log header and a checkpoint), then follows the primary's
// tick entries through a matchlog::MatchFollower, checking every tick's state hash; a divergent
// tick or entries it missed make it ask again. It publishes nothing to clients while it follows.
// When the primary's tick entries stop for --takeover-after-ticks ticks while the standby holds
// every tick the primary sent, it takes the match over: from the next tick it hosts it as a
// MatchServer (same match id, clients, entities, command sequences; clients do not rejoin).
//
// Threads: run() is the follow loop, the only thread that touches the follower's match; Fast DDS
// listener threads only queue entries and answers; status() may be called from any thread.
#include <cstdint>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "throng/matchlog/follower.h"
#include "throng/server/server_options.h"

namespace throng::server {

struct StandbyStatus {
  std::string match_id;              // the primary's, once it answered
  bool synced = false;               // the standby holds the primary's match
  std::uint64_t first_sync_tick = 0; // the tick of the first answer it started from
  bool following = false;            // ... and every tick up to `tick` matched the primary's hash
  std::uint64_t tick = 0;            // ticks applied
  std::uint64_t state_hash = 0;      // the standby's match after `tick`
  std::uint64_t primary_tick = 0;    // the newest tick entry received
  std::uint64_t entries_received = 0;
  std::uint64_t entries_refused = 0;  // malformed entries (the follower refused them)
  std::uint64_t requests_sent = 0;
  std::uint64_t syncs_received = 0;   // answers addressed to this standby
  std::uint64_t syncs_refused = 0;    // answers whose header or checkpoint did not load
  std::uint64_t entries_dropped_waiting = 0;  // entries dropped before the first answer (bounded wait)
  std::uint64_t entries_foreign = 0;  // entries of another match's primary on the same domain (ignored)
  bool primary_ended = false;         // an applied tick said the primary began its shutdown
  bool took_over = false;             // the standby now hosts the match (primary_summary())
  matchlog::FollowerStats follower;
  // The last divergence a checkpoint ended: first_tick, compared_at, objects [{object, what}], note
  // (null: none).
  nlohmann::json divergence;
};

class StandbyServer {
 public:
  // Creates the DDS participant (the server identity with --security). Throws std::exception
  // naming what failed.
  explicit StandbyServer(const ServerOptions& options);
  ~StandbyServer();
  StandbyServer(const StandbyServer&) = delete;
  StandbyServer& operator=(const StandbyServer&) = delete;

  // Follows until the primary ends the match, --duration passes, request_stop() is called or
  // SIGINT/SIGTERM arrives (when handle_signals). Prints the summary; returns the exit code: 0, 3
  // when the standby's match was diverged from the primary's at the end, 4 when it never had it.
  // After a takeover it hosts the match and returns MatchServer::run's code.
  int run(bool handle_signals = true);
  void request_stop();  // thread-safe

  StandbyStatus status() const;  // thread-safe
  // The port its admin endpoint listens on while it follows (--admin-port 0: the one the system
  // chose), after a takeover the new primary's; 0 without one or before run() opened it.
  // Thread-safe.
  std::uint16_t admin_port() const;
  nlohmann::json summary() const;   // the standby's figures (up to a takeover)
  // After a takeover: the hosted match's summary (MatchServer::summary()); null before.
  nlohmann::json primary_summary() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace throng::server
