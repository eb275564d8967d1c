#pragma once
// What one bot measures, fed with timestamps by its owner (no clock inside, so tests can feed
// exact times). Not thread-safe: the Bot serializes access.
//
//  - command -> applied latency: for every command expected to be accepted, from its send time to
//    the receive time of the first snapshot whose last_applied_sequence >= its sequence.
//  - snapshots: samples and payload bytes received, inter-arrival time between consecutive
//    snapshots, missed ticks (a tick jump of k > 1 counts k - 1), out-of-order/duplicate samples.
//  - join time: launch -> first snapshot.
//  - staleness: how old the newest snapshot is when it arrives, against the server's tick clock:
//    (arrival - tick x tick period) less the smallest such offset seen, i.e. how much later than
//    the path's fastest delivery it came. A stream that falls behind (TCP holding samples behind
//    a loss) shows here even when no tick is missed. Measured once the tick period is known.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>

#include "throng/client_sim/behavior.h"
#include "throng/client_sim/stats.h"

namespace throng::client_sim {

using Clock = std::chrono::steady_clock;
using TimePoint = Clock::time_point;

inline double ms_between(TimePoint a, TimePoint b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

struct CommandCounts {
  std::uint64_t sent = 0;
  std::uint64_t expect_accept = 0, expect_reject = 0, expect_unknown = 0;
  std::uint64_t applied = 0;  // expected-accepted commands seen applied
};

struct SnapshotCounts {
  std::uint64_t samples = 0;
  std::uint64_t bytes = 0;
  std::uint64_t missed_ticks = 0;
  // The most ticks missed in a row: what a player saw freeze (a server that stalled or was
  // replaced), where missed_ticks also sums scattered single losses.
  std::uint64_t longest_gap_ticks = 0;
  std::uint64_t out_of_order = 0;  // tick not newer than the newest seen (dropped)
};

class BotMetrics {
 public:
  void on_launch(TimePoint t) { launch_ = t; }
  void on_command_sent(std::uint32_t sequence, Expect expect, TimePoint t);
  // Every received sample (bytes, arrival, ticks).
  void on_snapshot_received(std::uint64_t tick, std::size_t wire_bytes, TimePoint t);
  // A snapshot the world accepted: resolves pending commands.
  void on_applied_sequence(std::uint32_t last_applied_sequence, TimePoint t);

  const CommandCounts& commands() const { return commands_; }
  const SnapshotCounts& snapshots() const { return snapshots_; }
  const Samples& latency_ms() const { return latency_ms_; }
  const Samples& interarrival_ms() const { return interarrival_ms_; }
  const Samples& staleness_ms() const { return staleness_ms_; }
  // The server's tick period (from its match info); 0 until known.
  void set_tick_ms(double ms) { tick_ms_ = ms; }
  std::optional<double> join_ms() const;
  std::optional<TimePoint> first_snapshot() const { return first_snapshot_; }
  std::optional<TimePoint> last_snapshot() const { return last_snapshot_; }
  std::size_t pending_commands() const { return pending_.size(); }
  // The bot joins again as a new client (its server is gone): commands still waiting were never
  // applied and are forgotten, and the new client's ticks are not compared with the old one's. The
  // arrival times go on, so the wait for the next snapshot shows the whole outage.
  void on_rejoin();

  // Latencies measured since the last call (for the live progress line).
  Samples take_window_latency();

 private:
  struct Pending {
    std::uint32_t sequence;
    TimePoint sent;
  };
  std::optional<TimePoint> launch_;
  std::optional<TimePoint> first_snapshot_, last_snapshot_;
  std::optional<std::uint64_t> newest_tick_;
  std::deque<Pending> pending_;
  CommandCounts commands_;
  SnapshotCounts snapshots_;
  Samples latency_ms_, interarrival_ms_, window_latency_ms_, staleness_ms_;
  double tick_ms_ = 0;
  std::optional<double> min_offset_ms_;
};

}  // namespace throng::client_sim
