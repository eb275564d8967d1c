#pragma once
// A following standby's Prometheus metrics (all named throng_standby_*), served on --admin-port
// while it follows, so that an orchestrator and an operator can see a standby that has fallen
// behind or diverged before it is needed. After a takeover the new primary serves the server's
// own metrics (server_metrics.h) on the same port.
#include "throng/admin/metrics.h"

namespace throng::server {

struct StandbyStatus;

struct StandbyMetrics {
  explicit StandbyMetrics(admin::MetricsRegistry& registry);
  // Sets every metric from the standby's status (the follow loop calls it; no allocation).
  void update(const StandbyStatus& s);

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
