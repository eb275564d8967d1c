#pragma once
// What `throng-replay play` puts on DDS for each played tick: the same topics, QoS and order as
// throng-server (server/app/src/match_server.cpp), from the re-simulated match instead of a live
// one, plus the watchers' streams (play_watchers.h).
//
// Per tick, in the server's order: the logged clients' snapshots (each on its own partition;
// a client that joined this tick has no channel yet, so, as live, its first one goes nowhere),
// then the clients' channel opens/closes, join and param replies, match info when it changed;
// then the watchers: their joins/leaves, commands (ignored), parameter updates (refused), and
// their snapshots; server stats once per logged second.
#include <chrono>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "play_watchers.h"
#include "throng/matchlog/log_player.h"
#include "throng/protocol/dds_transport.h"

namespace throng::replay {

struct SessionTotals {
  std::uint64_t ticks_played = 0;
  std::uint64_t hash_mismatches = 0;
  std::uint64_t first_mismatch_tick = 0;
  std::uint64_t param_updates_refused = 0;
  std::uint64_t inputs_dropped = 0;  // requests beyond the inbox cap (a flood), never queued
};

class PlaySession {
 public:
  using Clock = std::chrono::steady_clock;
  PlaySession(matchlog::LogPlayer& player, protocol::ServerTransport& transport, WatcherOptions watcher_options);

  // Starts the transport's readers and publishes the match info of the player's current tick.
  void start();
  // After player.seek(): opens/closes the logged clients' channels to match the clients
  // connected now, republishes the match info (a seek back may change its state and version).
  void after_seek(const matchlog::SeekResult& seek);
  // Publishes what the player's last step() produced and serves the watchers. work_s: how long
  // the previous tick's work took (for the stats' tick times); overruns: the schedule's count.
  void publish_tick(Clock::time_point now, double work_s, std::uint64_t overruns);
  // The match ends: refuse watchers, publish "ended" and the final stats, wait (bounded) until
  // readers acknowledged them.
  void end(std::uint64_t overruns);

  const SessionTotals& totals() const { return totals_; }
  const WatcherTotals& watcher_totals() const { return watchers_.totals(); }
  std::size_t watcher_count() const { return watchers_.count(); }
  bool last_tick_mismatched() const { return last_mismatch_; }

 private:
  struct Inbox {
    std::mutex mutex;
    std::vector<protocol::JoinRequest> joins;
    std::vector<protocol::ParamUpdate> params;
    std::vector<std::uint32_t> command_clients;
    std::uint64_t dropped = 0;
  };
  void serve_watchers(Clock::time_point now, bool ending);
  void apply_channels(const WatcherChanges& changes);
  void publish_stats(std::uint64_t overruns, bool ended);

  matchlog::LogPlayer& player_;
  protocol::ServerTransport& transport_;
  Watchers watchers_;
  Inbox inbox_;
  // Logged clients with an open channel: id -> partition (as their join events named it).
  std::map<std::uint32_t, std::string> logged_channels_;
  // Drained inbox and reused buffers (the tick does not allocate once warm).
  std::vector<protocol::JoinRequest> joins_;
  std::vector<protocol::ParamUpdate> params_;
  std::vector<std::uint32_t> command_clients_;
  std::vector<protocol::Snapshot> watcher_snapshots_;
  WatcherChanges changes_;
  std::vector<double> work_window_;  // tick work times since the last stats
  std::uint64_t push_events_ = 0;
  SessionTotals totals_;
  bool last_mismatch_ = false;
};

}  // namespace throng::replay
