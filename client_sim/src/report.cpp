#include "throng/client_sim/report.h"

#include <algorithm>

#include <fmt/format.h>

namespace throng::client_sim {

namespace {
nlohmann::json summary_json(const Summary& s) {
  return {{"count", s.count}, {"mean", s.mean}, {"p50", s.p50}, {"p90", s.p90}, {"p99", s.p99}, {"max", s.max}};
}
nlohmann::json commands_json(const CommandCounts& c) {
  return {{"sent", c.sent},
          {"applied", c.applied},
          {"expect_accept", c.expect_accept},
          {"expect_reject", c.expect_reject},
          {"expect_unknown", c.expect_unknown}};
}
nlohmann::json pose_json(const std::optional<ObjectState>& p) {
  if (!p) return nullptr;
  return {{"x", p->x}, {"y", p->y}, {"z", p->z}, {"yaw", p->yaw}};
}
bool failed(const BotReport& b) { return b.state == "refused" || b.state == "timed_out"; }
}  // namespace

Aggregate aggregate(const RunReport& report) {
  Aggregate a;
  a.clients = report.bots.size();
  Samples latency, interarrival, join, staleness;
  double kbps_sum = 0;
  std::size_t kbps_n = 0;
  double active_sum = 0;
  for (const auto& b : report.bots) {
    if (failed(b)) ++a.join_failed;
    if (b.join_ms) {
      ++a.joined;
      join.add(*b.join_ms);
    }
    latency.append(b.latency_ms);
    interarrival.append(b.interarrival_ms);
    staleness.append(b.staleness_ms);
    a.gap_ticks += b.snapshots.missed_ticks;
    a.longest_gap_ticks = std::max(a.longest_gap_ticks, b.snapshots.longest_gap_ticks);
    a.rejoins += b.rejoins;
    a.bots_rejoined += b.rejoins > 0 ? 1 : 0;
    a.out_of_order += b.snapshots.out_of_order;
    a.decode_errors += b.decode_errors;
    a.snapshots += b.snapshots.samples;
    a.bytes += b.snapshots.bytes;
    a.commands.sent += b.commands.sent;
    a.commands.applied += b.commands.applied;
    a.commands.expect_accept += b.commands.expect_accept;
    a.commands.expect_reject += b.commands.expect_reject;
    a.commands.expect_unknown += b.commands.expect_unknown;
    if (b.active_s > 0 && b.snapshots.samples > 0) {
      const double k = b.kbit_per_s();
      kbps_sum += k;
      ++kbps_n;
      a.kbit_per_s_max = std::max(a.kbit_per_s_max, k);
      active_sum += b.active_s;
    }
  }
  a.latency_ms = latency.summary();
  a.interarrival_ms = interarrival.summary();
  a.staleness_ms = staleness.summary();
  a.join_ms = join.summary();
  a.kbit_per_s_mean = kbps_n ? kbps_sum / static_cast<double>(kbps_n) : 0.0;
  a.snapshots_per_s_per_client = active_sum > 0 ? static_cast<double>(a.snapshots) / active_sum : 0.0;
  return a;
}

nlohmann::json to_json(const protocol::ServerStats& s) {
  return {{"tick", s.tick},
          {"tick_hz", s.tick_hz},
          {"clients", s.clients},
          {"bodies", s.bodies},
          {"tick_ms_p50", s.tick_ms_p50},
          {"tick_ms_p99", s.tick_ms_p99},
          {"tick_ms_max", s.tick_ms_max},
          {"overruns", s.overruns},
          {"commands_accepted", s.commands_accepted},
          {"commands_rejected", s.commands_rejected},
          {"snapshot_bytes", s.snapshot_bytes},
          {"snapshot_samples", s.snapshot_samples},
          {"push_events", s.push_events},
          {"state_hash", s.state_hash},
          {"state", s.state == protocol::MatchState::ended ? "ended" : "running"}};
}

nlohmann::json to_json(const BotReport& b) {
  nlohmann::json j = {{"name", b.name},
                      {"behavior", b.behavior},
                      {"state", b.state},
                      {"client_id", b.client_id},
                      {"entity", b.entity},
                      {"faction", b.faction},
                      {"commands", commands_json(b.commands)},
                      {"snapshots",
                       {{"received", b.snapshots.samples},
                        {"bytes", b.snapshots.bytes},
                        {"gap_ticks", b.snapshots.missed_ticks},
                        {"longest_gap_ticks", b.snapshots.longest_gap_ticks},
                        {"out_of_order", b.snapshots.out_of_order},
                        {"decode_errors", b.decode_errors}}},
                      {"last_applied_sequence", b.last_applied_sequence},
                      {"last_tick", b.last_tick},
                      {"join_ms", b.join_ms ? nlohmann::json(*b.join_ms) : nlohmann::json(nullptr)},
                      {"active_s", b.active_s},
                      {"kbit_per_s", b.kbit_per_s()},
                      {"latency_ms", summary_json(b.latency_ms.summary())},
                      {"snapshot_interarrival_ms", summary_json(b.interarrival_ms.summary())},
                      {"snapshot_staleness_ms", summary_json(b.staleness_ms.summary())},
                      {"first_pose", pose_json(b.first_pose)},
                      {"last_pose", pose_json(b.last_pose)},
                      {"moved_m", b.moved_m},
                      {"world_objects", b.world_objects},
                      {"rejoins", b.rejoins}};
  if (!b.refused_reason.empty()) j["refused_reason"] = b.refused_reason;
  return j;
}

nlohmann::json to_json(const RunReport& r) {
  const Aggregate a = aggregate(r);
  nlohmann::json per_client = nlohmann::json::array();
  for (const auto& b : r.bots) per_client.push_back(to_json(b));
  nlohmann::json j = {
      {"clients", a.clients},
      {"joined", a.joined},
      {"join_failed", a.join_failed},
      {"tick_hz", r.tick_hz},
      {"duration_s", r.duration_s},
      {"behavior", r.behavior},
      {"latency_ms", summary_json(a.latency_ms)},
      {"snapshot_interarrival_ms", summary_json(a.interarrival_ms)},
      {"snapshot_staleness_ms", summary_json(a.staleness_ms)},
      {"snapshot_gap_ticks", a.gap_ticks},
      {"max_snapshot_gap_ticks", a.longest_gap_ticks},
      {"rejoins", a.rejoins},
      {"bots_rejoined", a.bots_rejoined},
      {"snapshots",
       {{"received", a.snapshots},
        {"bytes", a.bytes},
        {"out_of_order", a.out_of_order},
        {"decode_errors", a.decode_errors},
        {"per_s_per_client", a.snapshots_per_s_per_client}}},
      {"kbit_per_s_per_client", {{"mean", a.kbit_per_s_mean}, {"max", a.kbit_per_s_max}}},
      {"join_ms", summary_json(a.join_ms)},
      {"commands", commands_json(a.commands)},
      {"server_stats", r.server_stats ? to_json(*r.server_stats) : nlohmann::json(nullptr)},
      {"per_client", per_client},
  };
  if (r.ramp) j["ramp"] = to_json(*r.ramp);
  return j;
}

std::string to_text(const RunReport& r) {
  const Aggregate a = aggregate(r);
  const double period_ms = 1000.0 / std::max<std::uint32_t>(1, r.tick_hz);
  std::string s;
  s += fmt::format("throng-bots: {} clients ({}), {:.1f} s at {} Hz (tick {:.1f} ms)\n", a.clients, r.behavior,
                   r.duration_s, r.tick_hz, period_ms);
  s += fmt::format("  joined            {} of {} ({} failed); join time p50 {:.0f} ms, p99 {:.0f} ms, max {:.0f} ms\n",
                   a.joined, a.clients, a.join_failed, a.join_ms.p50, a.join_ms.p99, a.join_ms.max);
  s += fmt::format("  cmd->applied      p50 {:.1f} ms  p90 {:.1f} ms  p99 {:.1f} ms  max {:.1f} ms  ({} samples; "
                   "p50 {:.2f} ticks, p99 {:.2f} ticks)\n",
                   a.latency_ms.p50, a.latency_ms.p90, a.latency_ms.p99, a.latency_ms.max, a.latency_ms.count,
                   a.latency_ms.p50 / period_ms, a.latency_ms.p99 / period_ms);
  s += fmt::format("  commands          {} sent, {} applied (expected: {} accept, {} reject, {} either)\n",
                   a.commands.sent, a.commands.applied, a.commands.expect_accept, a.commands.expect_reject,
                   a.commands.expect_unknown);
  s += fmt::format("  snapshots         {} received, {:.1f}/s per client, {} missed ticks (at most {} in a row), {} "
                   "out of order, {} malformed\n",
                   a.snapshots, a.snapshots_per_s_per_client, a.gap_ticks, a.longest_gap_ticks, a.out_of_order,
                   a.decode_errors);
  if (a.rejoins > 0)
    s += fmt::format("  rejoins           {} bots joined again as new clients ({} joins in all): their snapshots stopped\n",
                     a.bots_rejoined, a.rejoins);
  s += fmt::format("  inter-arrival     p50 {:.1f} ms  p90 {:.1f} ms  p99 {:.1f} ms  max {:.1f} ms\n",
                   a.interarrival_ms.p50, a.interarrival_ms.p90, a.interarrival_ms.p99, a.interarrival_ms.max);
  if (a.staleness_ms.count > 0)
    s += fmt::format("  staleness         p50 {:.1f} ms  p99 {:.1f} ms  max {:.1f} ms  (newest snapshot's age beyond the "
                     "path's fastest delivery, on the server's tick clock)\n",
                     a.staleness_ms.p50, a.staleness_ms.p99, a.staleness_ms.max);
  s += fmt::format("  bandwidth         {:.1f} kbit/s per client (max {:.1f}), {:.2f} MB total\n", a.kbit_per_s_mean,
                   a.kbit_per_s_max, static_cast<double>(a.bytes) / 1e6);
  if (r.server_stats) {
    const auto& st = *r.server_stats;
    s += fmt::format("  server (last)     tick {} at {} Hz, {} clients, {} bodies, tick p50 {:.2f} ms p99 {:.2f} ms "
                     "max {:.2f} ms, {} overruns, commands {} accepted / {} rejected\n",
                     st.tick, st.tick_hz, st.clients, st.bodies, st.tick_ms_p50, st.tick_ms_p99, st.tick_ms_max,
                     st.overruns, st.commands_accepted, st.commands_rejected);
  } else {
    s += "  server            no ServerStats received\n";
  }
  if (r.bots.size() <= 20) {
    s += "  per client:\n";
    for (const auto& b : r.bots) {
      const Summary l = b.latency_ms.summary();
      s += fmt::format("    {:<24} {:<9} id {:>4} sent {:>6} applied {:>6} snaps {:>6} gaps {:>3} lat p50 {:>6.1f} "
                       "p99 {:>6.1f} ms  {:>6.1f} kbit/s  moved {:.1f} m\n",
                       b.name, b.state, b.client_id, b.commands.sent, b.commands.applied, b.snapshots.samples,
                       b.snapshots.missed_ticks, l.p50, l.p99, b.kbit_per_s(), b.moved_m);
    }
  }
  if (r.ramp) {
    s += "  ramp:\n";
    for (const auto& st : r.ramp->steps) {
      s += fmt::format("    {:>5} clients: {} ticks, {} overruns, tick p99 {:.2f} ms, {} missed snapshots, latency p50 "
                       "{:.1f} p99 {:.1f} ms, {:.1f} kbit/s/client -> {}\n",
                       st.clients, st.ticks, st.overruns, st.tick_ms_p99, st.missed_snapshots, st.latency_p50_ms,
                       st.latency_p99_ms, st.kbit_per_s_per_client, st.verdict);
    }
    s += fmt::format("  largest sustained: {} clients ({})\n", r.ramp->max_sustained, r.ramp->stopped_because);
  }
  return s;
}

}  // namespace throng::client_sim
