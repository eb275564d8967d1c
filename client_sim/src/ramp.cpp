#include "throng/client_sim/ramp.h"

#include <algorithm>

#include <fmt/format.h>

namespace throng::client_sim {

void judge_step(RampStep& s, const RampOptions& o) {
  std::vector<std::string> why;
  if (s.joined < s.clients) why.push_back(fmt::format("{} of {} bots joined", s.joined, s.clients));
  if (!s.server_stats_seen) {
    why.push_back("no ServerStats from the server in the window");
  } else if (s.ticks == 0) {
    why.push_back("the server did not tick");
  } else if (static_cast<double>(s.overruns) >= o.max_overrun_fraction * static_cast<double>(s.ticks)) {
    why.push_back(fmt::format("{} overruns in {} ticks ({:.2f}% >= {:.2f}%)", s.overruns, s.ticks,
                              100.0 * static_cast<double>(s.overruns) / static_cast<double>(s.ticks),
                              100.0 * o.max_overrun_fraction));
  }
  if (s.missed_snapshots > 0) why.push_back(fmt::format("{} missed snapshots", s.missed_snapshots));
  s.pass = why.empty();
  if (s.pass) {
    s.verdict = "ok";
  } else {
    s.verdict.clear();
    for (std::size_t i = 0; i < why.size(); ++i) s.verdict += (i ? "; " : "") + why[i];
  }
}

bool record_step(RampResult& r, RampStep step, const RampOptions& o) {
  judge_step(step, o);
  const bool pass = step.pass;
  const std::uint32_t clients = step.clients;
  r.steps.push_back(std::move(step));
  if (!pass) {
    r.stopped_because = fmt::format("step with {} clients failed: {}", clients, r.steps.back().verdict);
    return false;
  }
  r.max_sustained = std::max(r.max_sustained, clients);
  if (clients >= o.max_clients) {
    r.stopped_because = fmt::format("reached --ramp-max {}", o.max_clients);
    return false;
  }
  return true;
}

std::uint32_t next_clients(std::uint32_t current, const RampOptions& o) {
  return std::min(o.max_clients, current + std::max<std::uint32_t>(1, o.step));
}

nlohmann::json to_json(const RampStep& s) {
  return {{"clients", s.clients},
          {"joined", s.joined},
          {"window_s", s.window_s},
          {"server_stats_seen", s.server_stats_seen},
          {"ticks", s.ticks},
          {"overruns", s.overruns},
          {"tick_ms_p99", s.tick_ms_p99},
          {"missed_snapshots", s.missed_snapshots},
          {"latency_ms", {{"p50", s.latency_p50_ms}, {"p99", s.latency_p99_ms}}},
          {"kbit_per_s_per_client", s.kbit_per_s_per_client},
          {"pass", s.pass},
          {"verdict", s.verdict}};
}

nlohmann::json to_json(const RampResult& r) {
  nlohmann::json steps = nlohmann::json::array();
  for (const auto& s : r.steps) steps.push_back(to_json(s));
  return {{"max_sustained_clients", r.max_sustained}, {"stopped_because", r.stopped_because}, {"steps", steps}};
}

}  // namespace throng::client_sim
