#pragma once
// A following standby's Prometheus metrics (all named throng_standby_*), served on --admin-port
// while it follows, so that an orchestrator and an operator can see a standby that has fallen
// behind or diverged before it is needed. After a takeover the new primary serves the server's
// own metrics (server_metrics.h) on the same port.
#include <cstdint>

#include "throng/admin/metrics.h"
#include "throng/matchlog/follower.h"

namespace throng::server {

struct StandbyStatus;

// The counts of the followers a standby had before its current one (the primary hosted another
// match since), so that its counters keep counting across matches.
struct StandbyTotals {
  std::uint64_t applied = 0, mismatches = 0, checkpoints = 0, gaps = 0;
  void add(const matchlog::FollowerStats& f) {
    applied += f.applied;
    mismatches += f.mismatches;
    checkpoints += f.checkpoints;
    gaps += f.gaps;
  }
};

struct StandbyMetrics {
  explicit StandbyMetrics(admin::MetricsRegistry& registry);
  // Sets every metric from the standby's status and its earlier followers' counts (the follow
  // loop calls it; no allocation).
  void update(const StandbyStatus& s, const StandbyTotals& earlier);

  admin::Gauge& following;
  admin::Gauge& tick;
  admin::Gauge& primary_tick;
  admin::Counter& ticks_applied;
  admin::Counter& mismatches;
  admin::Counter& checkpoints;
  admin::Counter& gaps;
  admin::Counter& entries_refused;
};

}  // namespace throng::server
