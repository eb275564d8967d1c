#pragma once
// Ramp mode's bookkeeping: one step = one client count held for a measuring window. A step
// passes when every bot joined, the server's tick overruns in the window stayed under
// max_overrun_fraction of its ticks, and no bot missed a snapshot. The driver (throng-bots) adds
// bots step by step and stops at the first failing step or at max_clients.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace throng::client_sim {

struct RampOptions {
  std::uint32_t start = 10;
  std::uint32_t step = 10;
  std::uint32_t max_clients = 200;
  double step_s = 10.0;                 // measuring window per step
  double settle_s = 2.0;                // after the step's bots joined, before measuring
  double max_overrun_fraction = 0.01;
};

struct RampStep {
  std::uint32_t clients = 0;       // bots launched
  std::uint32_t joined = 0;        // bots with a first snapshot
  double window_s = 0;
  bool server_stats_seen = false;  // ServerStats at both ends of the window
  std::uint64_t ticks = 0;         // server ticks in the window
  std::uint64_t overruns = 0;      // server overruns in the window
  double tick_ms_p99 = 0;          // worst ServerStats::tick_ms_p99 seen in the window
  std::uint64_t missed_snapshots = 0;  // bots' missed ticks in the window
  double latency_p50_ms = 0, latency_p99_ms = 0;
  double kbit_per_s_per_client = 0;
  bool pass = false;
  std::string verdict;             // "ok" or why it failed
};

struct RampResult {
  std::vector<RampStep> steps;
  std::uint32_t max_sustained = 0;  // largest passing client count (0 = none passed)
  std::string stopped_because;
};

// Fills step.pass and step.verdict from its measurements.
void judge_step(RampStep& step, const RampOptions& options);
// Appends a judged step; updates max_sustained. Returns whether the ramp should go on (the step
// passed and clients < max_clients); sets stopped_because when it should not.
bool record_step(RampResult& result, RampStep step, const RampOptions& options);
// The next client count after `current` (never above max_clients).
std::uint32_t next_clients(std::uint32_t current, const RampOptions& options);

nlohmann::json to_json(const RampStep& step);
nlohmann::json to_json(const RampResult& result);

}  // namespace throng::client_sim
