#pragma once
// The run report: per bot and aggregated figures, as a human summary and as JSON.
//
// JSON (to_json) top level: clients, joined, join_failed, tick_hz, duration_s, behavior,
// latency_ms {count,mean,p50,p90,p99,max}, snapshot_interarrival_ms {...}, snapshot_gap_ticks
// (total missed), snapshots {received, bytes, out_of_order, decode_errors, per_s_per_client},
// kbit_per_s_per_client {mean,max}, join_ms {count,p50,p90,p99,max}, commands {sent, applied,
// expect_accept, expect_reject, expect_unknown}, server_stats (last ServerStats seen, or null),
// per_client [...], and ramp (ramp mode only).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "throng/client_sim/bot_metrics.h"
#include "throng/client_sim/ramp.h"
#include "throng/client_sim/stats.h"
#include "throng/protocol/messages.h"

namespace throng::client_sim {

struct BotReport {
  std::string name;
  std::string behavior;
  std::string state;           // created, joining, joined, refused, timed_out, left
  std::string refused_reason;  // JoinReply::reason when refused
  std::uint32_t client_id = 0;
  std::uint32_t entity = 0;
  std::uint8_t faction = 0;
  CommandCounts commands;
  SnapshotCounts snapshots;
  std::uint64_t decode_errors = 0;
  std::uint32_t last_applied_sequence = 0;
  std::uint64_t last_tick = 0;
  std::optional<double> join_ms;
  double active_s = 0;         // first snapshot -> report time
  Samples latency_ms;
  Samples interarrival_ms;
  Samples staleness_ms;  // BotMetrics::staleness_ms
  std::optional<ObjectState> first_pose, last_pose;  // own entity
  double moved_m = 0;          // horizontal distance first_pose -> last_pose
  std::size_t world_objects = 0;
  std::uint32_t rejoins = 0;   // times it joined again after its snapshots stopped (--rejoin-after)

  double kbit_per_s() const { return active_s > 0 ? snapshots.bytes * 8.0 / 1000.0 / active_s : 0.0; }
};

struct RunReport {
  std::uint32_t tick_hz = 30;
  double duration_s = 0;
  std::string behavior;
  std::vector<BotReport> bots;
  std::optional<protocol::ServerStats> server_stats;  // last seen
  std::optional<RampResult> ramp;
};

struct Aggregate {
  std::size_t clients = 0, joined = 0, join_failed = 0;
  Summary latency_ms, interarrival_ms, join_ms, staleness_ms;
  std::uint64_t gap_ticks = 0, out_of_order = 0, decode_errors = 0;
  std::uint64_t longest_gap_ticks = 0;  // the longest run of missed ticks at any bot
  std::uint64_t rejoins = 0;            // joins again, over all bots (--rejoin-after)
  std::size_t bots_rejoined = 0;        // bots that joined again at least once
  std::uint64_t snapshots = 0, bytes = 0;
  double snapshots_per_s_per_client = 0;
  double kbit_per_s_mean = 0, kbit_per_s_max = 0;  // over bots that received snapshots
  CommandCounts commands;
};

Aggregate aggregate(const RunReport& report);
nlohmann::json to_json(const protocol::ServerStats& stats);
nlohmann::json to_json(const BotReport& bot);
nlohmann::json to_json(const RunReport& report);
std::string to_text(const RunReport& report);

}  // namespace throng::client_sim
