#include "ramp_mode.h"

#include <algorithm>

#include <fmt/format.h>

#include "driver.h"

namespace throng::bots {

namespace {

struct Mark {
  std::size_t stats_seen = 0;  // ServerStats received so far
  client_sim::FleetProgress progress;
  std::vector<std::size_t> latency_counts;  // per bot: latency samples so far
  client_sim::TimePoint at;
};

Mark mark(client_sim::Fleet& fleet) {
  Mark m;
  m.stats_seen = fleet.server_stats_history().size();
  m.progress = fleet.progress();
  for (const auto& r : fleet.reports()) m.latency_counts.push_back(r.latency_ms.size());
  m.at = client_sim::Clock::now();
  return m;
}

const char* end_reason(DriveEnd e) {
  switch (e) {
    case DriveEnd::interrupted: return "interrupted";
    case DriveEnd::server_ended: return "the server's match ended";
    default: return "";
  }
}

}  // namespace

client_sim::RampResult run_ramp(client_sim::Fleet& fleet, const Options& o, const std::atomic<bool>& stop,
                                ProgressLine& progress) {
  const auto& ro = o.ramp_options;
  client_sim::RampResult result;
  std::uint32_t clients = std::max<std::uint32_t>(1, std::min(ro.start, ro.max_clients));
  fleet.launch(clients);
  for (;;) {
    // Every bot of this step joined (or failed), then a settling pause before measuring.
    auto e = drive(fleet, o.join_timeout_s + 2.0, stop, progress, [&] {
      const auto p = fleet.progress();
      return p.active + p.failed >= p.launched;
    });
    if (e == DriveEnd::interrupted || e == DriveEnd::server_ended) {
      result.stopped_because = end_reason(e);
      break;
    }
    e = drive_for(fleet, ro.settle_s, stop, progress);
    if (e == DriveEnd::interrupted || e == DriveEnd::server_ended) {
      result.stopped_because = end_reason(e);
      break;
    }
    const Mark a = mark(fleet);
    e = drive_for(fleet, ro.step_s, stop, progress);
    if (e == DriveEnd::interrupted || e == DriveEnd::server_ended) {
      result.stopped_because = fmt::format("{} during the step with {} clients", end_reason(e), clients);
      break;
    }
    const Mark b = mark(fleet);

    client_sim::RampStep step;
    step.clients = clients;
    step.joined = static_cast<std::uint32_t>(b.progress.active);
    step.window_s = std::chrono::duration<double>(b.at - a.at).count();
    // The server's counters over the window: from the last ServerStats before it (or the first
    // inside it, when none came before) to the last one inside it.
    const auto history = fleet.server_stats_history();
    const std::size_t end_n = std::min(b.stats_seen, history.size());
    const std::size_t first = a.stats_seen > 0 ? a.stats_seen - 1 : 0;
    step.server_stats_seen = end_n > first + 1 && history[end_n - 1].tick > history[first].tick;
    if (step.server_stats_seen) {
      const auto& s0 = history[first];
      const auto& s1 = history[end_n - 1];
      step.ticks = s1.tick - s0.tick;
      step.overruns = s1.overruns - std::min(s1.overruns, s0.overruns);
      for (std::size_t k = first + 1; k < end_n; ++k)
        step.tick_ms_p99 = std::max(step.tick_ms_p99, static_cast<double>(history[k].tick_ms_p99));
    }
    step.missed_snapshots = b.progress.missed_ticks - a.progress.missed_ticks;
    client_sim::Samples lat;
    const auto reports = fleet.reports();
    for (std::size_t i = 0; i < reports.size(); ++i) {
      const auto v = reports[i].latency_ms.values();
      const std::size_t from = i < a.latency_counts.size() ? a.latency_counts[i] : 0;
      for (std::size_t k = from; k < v.size(); ++k) lat.add(v[k]);
    }
    const auto ls = lat.summary();
    step.latency_p50_ms = ls.p50;
    step.latency_p99_ms = ls.p99;
    if (b.progress.active > 0 && step.window_s > 0)
      step.kbit_per_s_per_client = static_cast<double>(b.progress.bytes - a.progress.bytes) * 8.0 / 1000.0 /
                                   step.window_s / static_cast<double>(b.progress.active);

    progress.finish();
    const bool go_on = client_sim::record_step(result, step, ro);
    const auto& judged = result.steps.back();
    fmt::print(stderr, "ramp: {} clients: {} ticks, {} overruns, tick p99 {:.2f} ms, {} missed snapshots, latency p50 "
                       "{:.1f} ms p99 {:.1f} ms -> {}\n",
               judged.clients, judged.ticks, judged.overruns, judged.tick_ms_p99, judged.missed_snapshots,
               judged.latency_p50_ms, judged.latency_p99_ms, judged.verdict);
    if (!go_on) break;
    const std::uint32_t next = client_sim::next_clients(clients, ro);
    fleet.launch(next - clients);
    clients = next;
  }
  return result;
}

}  // namespace throng::bots
