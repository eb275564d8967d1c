#pragma once
// The server's Prometheus metrics (all named throng_*), registered once at start-up so the tick
// never allocates for them (atomics, and a histogram's own short lock). What each one means is in
// its help text, which /metrics serves.
#include <array>

#include "throng/admin/metrics.h"
#include "throng/match/match.h"

namespace throng::server {

struct ServerMetrics {
  explicit ServerMetrics(admin::MetricsRegistry& registry);

  admin::Counter& ticks;
  admin::Counter& overruns;
  admin::Counter& skipped_ticks;
  admin::Histogram& tick_seconds;
  admin::Histogram& phase_seconds_step;
  admin::Histogram& phase_seconds_publish;
  admin::Gauge& clients;
  admin::Gauge& bodies;
  admin::Counter& joins_accepted;
  admin::Counter& joins_refused;
  admin::Counter& joins_foreign;         // joins/leaves for another participant's client
  admin::Counter& param_not_operator;    // parameter changes from a participant that is no operator
  admin::Counter& participants_refused;  // DDS Security: remote participants that failed authentication
  admin::Counter& leaves;
  admin::Counter& timeouts;
  admin::Counter& commands_accepted;
  std::array<admin::Counter*, match::kRejectReasonCount> commands_rejected{};
  admin::Counter& input_queue_dropped;
  admin::Counter& param_updates_applied;
  admin::Counter& param_updates_rejected;
  admin::Counter& snapshot_samples;
  admin::Counter& snapshot_bytes;
  admin::Counter& snapshot_poses;
  admin::Counter& other_samples;
  admin::Counter& other_bytes;
  admin::Counter& push_events;
  admin::Counter& contacts_samples;
  admin::Counter& contacts_bytes;
  admin::Counter& contacts_refused;
  admin::Gauge& view_error_max_m;
  admin::Gauge& state_hash_low32;
  admin::Gauge& log_backlog_ticks;
  admin::Gauge& log_bytes;
  admin::Counter& log_ticks_dropped;
  admin::Counter& log_keyframes_dropped;
  admin::Counter& log_write_errors;
  // The world's step (StepStats): where its time goes and how often it searches.
  admin::Histogram& world_phase_move;
  admin::Histogram& world_phase_params;
  admin::Histogram& world_phase_search;
  admin::Histogram& world_phase_solve;
  admin::Counter& world_searches;
  admin::Counter& world_second_searches;
  admin::Counter& world_capped_bodies;
  admin::Counter& world_tunnel_clamps;
  admin::Counter& world_pile_relief_bodies;
  admin::Gauge& world_candidate_pairs;
  admin::Gauge& world_solver_max_pen;

  // Everything above that a StepStats feeds (no allocation).
  void observe_step(const StepStats& s);
};

}  // namespace throng::server
