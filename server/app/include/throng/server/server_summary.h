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

struct SummaryInputs {
  const match::Match& match;
  const ClientLedger& ledger;
  const DurationStats& tick;
  const DurationStats& publish;
  const TickSchedule& schedule;
  protocol::TransportCounters published;
  double wall_seconds = 0;
  std::uint64_t push_events = 0;
  std::uint64_t poses = 0;
  double view_error_max_m = 0;
  std::string scene_name;
};

nlohmann::json make_summary(const SummaryInputs& in);
std::string format_summary(const nlohmann::json& summary);

}  // namespace throng::server
