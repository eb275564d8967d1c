#pragma once
// The end-of-match summary: one JSON document (--summary-json, and what tests and bots compare
// against) and its human rendering on stdout.
#include <string>

#include <nlohmann/json.hpp>

#include "throng/match/match.h"
#include "throng/protocol/dds_transport.h"
#include "throng/server/client_ledger.h"
#include "throng/server/duration_stats.h"
#include "throng/server/tick_schedule.h"

namespace throng::server {

// Durations of the tick's named phases (match.h TickReport, plus publishing).
struct PhaseStats {
  DurationStats drain, apply, ai, step, snapshots, publish;
  void add(const match::TickReport& r, double publish_s) {
    drain.add(r.drain_us * 1e-6);
    apply.add(r.apply_us * 1e-6);
    ai.add(r.ai_us * 1e-6);
    step.add(r.step_us * 1e-6);
    snapshots.add(r.snapshots_us * 1e-6);
    publish.add(publish_s);
  }
};

struct SummaryInputs {
  const match::Match& match;
  const ClientLedger& ledger;
  const DurationStats& tick;
  const PhaseStats& phases;
  const TickSchedule& schedule;
  protocol::TransportCounters published;
  double wall_seconds = 0;
  std::uint64_t push_events = 0;
  std::uint64_t poses = 0;
  double view_error_max_m = 0;
  std::string scene_name;
  std::uint64_t joins_foreign = 0;       // joins/leaves for another participant's client
  std::uint64_t param_not_operator = 0;  // parameter changes refused: not an operator
  std::string end_reason{};              // duration, signal, empty, routed, stopped
};

nlohmann::json make_summary(const SummaryInputs& in);
std::string format_summary(const nlohmann::json& summary);

}  // namespace throng::server
