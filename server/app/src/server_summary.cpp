#include "throng/server/server_summary.h"

#include <fmt/format.h>

#include "throng/world/world.h"

namespace throng::server {

namespace {
nlohmann::json ms(const DurationStats& d) {
  return {{"p50", d.quantile(0.5) * 1e3}, {"p90", d.quantile(0.9) * 1e3}, {"p99", d.quantile(0.99) * 1e3},
          {"max", d.max() * 1e3}, {"mean", d.mean() * 1e3}};
}
}  // namespace

nlohmann::json make_summary(const SummaryInputs& in) {
  const auto& m = in.match;
  nlohmann::json j;
  j["match_id"] = m.match_info().match_id;
  j["scene"] = in.scene_name;
  j["tick_hz"] = m.config().tick_hz;
  j["ticks"] = m.tick_index();
  j["wall_seconds"] = in.wall_seconds;
  j["bodies"] = m.world().pos_x().size();
  j["overruns"] = in.schedule.overruns();
  j["skipped_ticks"] = in.schedule.skipped();
  j["tick_ms"] = ms(in.tick);
  j["tick_budget_ms"] = 1000.0 / m.config().tick_hz;
  const PhaseStats& ph = in.phases;
  j["publish_ms"] = ms(ph.publish);
  j["phase_ms"] = {{"drain", ms(ph.drain)}, {"apply", ms(ph.apply)}, {"ai", ms(ph.ai)}, {"step", ms(ph.step)},
                   {"snapshots", ms(ph.snapshots)}, {"publish", ms(ph.publish)}};
  j["commands_accepted"] = m.commands_accepted_total();
  std::uint64_t rejected = 0;
  nlohmann::json by_reason = nlohmann::json::object();
  for (std::size_t i = 0; i < match::kRejectReasonCount; ++i) {
    by_reason[match::to_string(static_cast<match::RejectReason>(i))] = m.rejected_by_reason()[i];
    rejected += m.rejected_by_reason()[i];
  }
  j["commands_rejected"] = rejected;
  j["rejected_by_reason"] = by_reason;
  j["input_queue_dropped"] = m.inputs().dropped();
  j["joins_foreign_participant"] = in.joins_foreign;
  j["param_updates_not_operator"] = in.param_not_operator;
  j["participants_refused"] = in.published.participants_refused;
  nlohmann::json clients = nlohmann::json::array();
  for (const auto& [id, r] : in.ledger.records()) {
    clients.push_back({{"client_id", r.client_id}, {"name", r.name}, {"entity", r.entity}, {"joined_tick", r.joined_tick},
                       {"departed_tick", r.departed_tick}, {"departure", r.departure},
                       {"commands_accepted", r.commands_accepted}, {"commands_rejected", r.commands_rejected},
                       {"snapshots_published", r.snapshots_published}, {"poses_published", r.poses_published}});
  }
  j["clients"] = clients;
  j["clients_connected_at_end"] = m.client_count();
  const double secs = in.wall_seconds > 0 ? in.wall_seconds : 1.0;
  const auto& p = in.published;
  j["snapshots"] = {{"samples", p.snapshot_samples},
                    {"bytes", p.snapshot_bytes},
                    {"poses", in.poses},
                    {"bytes_per_pose", in.poses ? static_cast<double>(p.snapshot_bytes) / static_cast<double>(in.poses) : 0.0},
                    {"bytes_per_sample", p.snapshot_samples ? static_cast<double>(p.snapshot_bytes) / static_cast<double>(p.snapshot_samples) : 0.0},
                    {"kbit_per_s_total", static_cast<double>(p.snapshot_bytes) * 8.0 / 1000.0 / secs}};
  j["other_topics"] = {{"samples", p.other_samples}, {"bytes", p.other_bytes}};
  j["push_events"] = in.push_events;
  j["view_error_max_m"] = in.view_error_max_m;
  j["state_hash"] = fmt::format("{:016x}", m.state_hash());
  j["end_reason"] = in.end_reason;
  return j;
}

std::string format_summary(const nlohmann::json& s) {
  std::string out;
  auto line = [&out](const std::string& l) { out += l + "\n"; };
  line("=== throng-server summary ===");
  line(fmt::format("match {}  scene {}  {} bodies  {} Hz", s["match_id"].get<std::string>(), s["scene"].get<std::string>(),
                   s["bodies"].get<std::uint64_t>(), s["tick_hz"].get<std::uint32_t>()));
  line(fmt::format("ticks {} in {:.1f} s  overruns {}  skipped {}{}", s["ticks"].get<std::uint64_t>(),
                   s["wall_seconds"].get<double>(), s["overruns"].get<std::uint64_t>(), s["skipped_ticks"].get<std::uint64_t>(),
                   s.value("end_reason", std::string()).empty() ? "" : "  ended by " + s["end_reason"].get<std::string>()));
  const auto& t = s["tick_ms"];
  line(fmt::format("tick ms  p50 {:.2f}  p90 {:.2f}  p99 {:.2f}  max {:.2f}  (budget {:.2f})", t["p50"].get<double>(),
                   t["p90"].get<double>(), t["p99"].get<double>(), t["max"].get<double>(), s["tick_budget_ms"].get<double>()));
  std::string phases;
  for (const char* name : {"drain", "apply", "ai", "step", "snapshots", "publish"})
    phases += fmt::format("  {} {:.2f}/{:.2f}", name, s["phase_ms"][name]["p50"].get<double>(), s["phase_ms"][name]["p99"].get<double>());
  line("phase ms p50/p99" + phases);
  line(fmt::format("clients {} ever, {} at end", s["clients"].size(), s["clients_connected_at_end"].get<std::uint32_t>()));
  std::string reasons;
  for (const auto& [k, v] : s["rejected_by_reason"].items())
    if (v.get<std::uint64_t>() > 0) reasons += fmt::format(" {}={}", k, v.get<std::uint64_t>());
  line(fmt::format("commands accepted {}  rejected {}{}", s["commands_accepted"].get<std::uint64_t>(),
                   s["commands_rejected"].get<std::uint64_t>(), reasons.empty() ? "" : " (" + reasons.substr(1) + ")"));
  const auto foreign = s["joins_foreign_participant"].get<std::uint64_t>();
  const auto not_operator = s["param_updates_not_operator"].get<std::uint64_t>();
  const auto refused = s["participants_refused"].get<std::uint64_t>();
  if (foreign + not_operator + refused > 0)
    line(fmt::format("refused  {} joins/leaves for another participant's client, {} parameter changes from non-operators, "
                     "{} participants by DDS Security",
                     foreign, not_operator, refused));
  const auto& sn = s["snapshots"];
  line(fmt::format("snapshots {} samples, {} poses, {:.2f} bytes/pose, {:.0f} bytes/sample, {:.0f} kbit/s total",
                   sn["samples"].get<std::uint64_t>(), sn["poses"].get<std::uint64_t>(), sn["bytes_per_pose"].get<double>(),
                   sn["bytes_per_sample"].get<double>(), sn["kbit_per_s_total"].get<double>()));
  line(fmt::format("push events {}  client view error max {:.3f} m  state hash {}", s["push_events"].get<std::uint64_t>(),
                   s["view_error_max_m"].get<double>(), s["state_hash"].get<std::string>()));
  return out;
}

}  // namespace throng::server
