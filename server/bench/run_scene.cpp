#include "run_scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <numeric>
#include <stdexcept>

#include <time.h>

#include <fmt/core.h>

#include "progress.h"
#include "throng/scene/build_scene.h"

namespace throng::bench {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// CPU time this thread has run [us] (not counting time it waited for a core).
double thread_cpu_us() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) * 1e-3;
}

}  // namespace

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  // Nearest rank: the smallest value with at least q of the samples at or below it.
  const auto n = values.size();
  std::size_t rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(n)));
  rank = std::clamp<std::size_t>(rank, 1, n);
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(rank - 1), values.end());
  return values[rank - 1];
}

Percentiles summarize(const std::vector<double>& values) {
  Percentiles p;
  if (values.empty()) return p;
  p.median = percentile(values, 0.5);
  p.p95 = percentile(values, 0.95);
  p.max = *std::max_element(values.begin(), values.end());
  p.mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  return p;
}

RunResult run_scene(const scene::SceneDef& def, const RunOptions& options) {
  RunResult r;
  r.scene = def.name;
  r.ticks = options.ticks;
  r.warmup = options.warmup;
  r.iterations = def.settings.iterations;
  r.threads = def.settings.threads;
  const auto t_build = Clock::now();
  scene::BuiltScene built = scene::build_scene(def);
  r.build_s = seconds_since(t_build);
  r.agents = built.world.body_count();

  std::vector<double> total, total_cpu, move, params, broad, solve, driver, candidates, iters;
  for (auto* v : {&total, &total_cpu, &move, &params, &broad, &solve, &driver, &candidates, &iters}) v->reserve(options.ticks);
  std::ofstream trace;
  if (!options.trace_path.empty()) {
    trace.open(options.trace_path);
    if (!trace) throw std::runtime_error("cannot write the trace file " + options.trace_path);
    trace << kTraceHeader << "\n";
  }
  ResidualOverTime& over = r.residual_over_time;
  over.from_tick = options.residual_from;
  Progress progress(def.name, options.warmup + options.ticks, options.progress);
  const auto t_run = Clock::now();
  for (std::uint64_t t = 0; t < options.warmup + options.ticks; ++t) {
    const auto t0 = Clock::now();
    built.driver.apply(built.world);
    const double driver_us = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
    const double cpu0 = thread_cpu_us();
    const StepStats& s = built.world.step();
    const double cpu_us = thread_cpu_us() - cpu0;
    progress.tick(t + 1, s.total_us);
    const std::uint64_t tick = t + 1;
    if (options.residual_from != 0 && tick >= options.residual_from) {
      // Outside the timed step: the metric's own grid costs about as much as a broadphase.
      const scene::ResidualStats now = scene::measure_residual(built.world);
      ++over.ticks_measured;
      if (now.max_pen_over_radius > over.worst_max_pen_over_radius || over.ticks_measured == 1) {
        over.worst_max_pen_over_radius = now.max_pen_over_radius;
        over.worst_max_tick = tick;
      }
      over.worst_p99_pen_over_radius = std::max(over.worst_p99_pen_over_radius, now.p99_pen_over_radius);
      if (now.max_pen_over_radius > 0.5) ++over.ticks_over_0_5_r;
      if (trace.is_open())
        trace << fmt::format("{},{:.1f},{:.6g},{:.6g},{},{:.6g},{},{},{:.1f},{:.1f},{},{},{}\n", tick, s.total_us,
                             now.max_pen_over_radius, now.p99_pen_over_radius, now.pairs_over_1pct,
                             s.max_pen_over_radius, s.iterations_used, s.tunnel_clamps, s.broadphase_us, s.solve_us,
                             s.pair_list_reused == 0 ? 1 : 0, s.second_search, s.pair_list_searched_ahead);
    }
    if (t < options.warmup) continue;
    total.push_back(s.total_us);
    total_cpu.push_back(cpu_us);
    move.push_back(s.move_us);
    params.push_back(s.params_us);
    broad.push_back(s.broadphase_us);
    solve.push_back(s.solve_us);
    driver.push_back(driver_us);
    candidates.push_back(s.candidate_pairs);
    iters.push_back(s.iterations_used);
    r.band_sweeps_total += s.band_sweeps;
    r.band_sweeps_skipped_total += s.band_sweeps_skipped;
    r.pair_list_reused_ticks += s.pair_list_reused;
    r.pair_list_searched_ahead_ticks += s.pair_list_searched_ahead;
    r.second_search_ticks += s.second_search;
    r.capped_bodies_max = std::max<std::uint64_t>(r.capped_bodies_max, s.capped_bodies);
    r.tunnel_clamps_total += s.tunnel_clamps;
    r.solver_max_pen_over_radius_last = s.max_pen_over_radius;
  }
  r.wall_s = seconds_since(t_run);
  progress.done();
  if (trace.is_open() && !trace.flush()) throw std::runtime_error("cannot write the trace file " + options.trace_path);

  r.tick_us = summarize(total);
  r.tick_cpu_us = summarize(total_cpu);
  r.move_us_median = percentile(move, 0.5);
  r.params_us_median = percentile(params, 0.5);
  r.broadphase_us_median = percentile(broad, 0.5);
  r.solve_us_median = percentile(solve, 0.5);
  r.driver_us_median = percentile(driver, 0.5);
  r.candidate_pairs_median = percentile(candidates, 0.5);
  r.iterations_used_mean = summarize(iters).mean;
  r.residual = scene::measure_residual(built.world);
  r.static_pen_max_over_radius = scene::static_pen_max_over_radius(built.world);
  r.state_hash = built.world.state_hash();
  if (r.residual.pair_tests > 200 * std::max<std::uint64_t>(r.agents, 1))
    fmt::print(stderr, "[{}] note: residual metric ran {} pair tests for {} bodies (a dense clump costs O(k^2))\n",
               def.name, r.residual.pair_tests, r.agents);
  return r;
}

std::string hash_hex(std::uint64_t h) { return fmt::format("{:016x}", h); }

nlohmann::ordered_json to_json(const RunResult& r) {
  nlohmann::ordered_json j;
  j["scene"] = r.scene;
  j["agents"] = r.agents;
  j["ticks"] = r.ticks;
  j["warmup"] = r.warmup;
  j["iterations"] = r.iterations;
  j["threads"] = r.threads;
  j["tick_us"] = {{"median", r.tick_us.median}, {"p95", r.tick_us.p95}, {"max", r.tick_us.max}, {"mean", r.tick_us.mean}};
  j["tick_cpu_us"] = {{"median", r.tick_cpu_us.median}, {"p95", r.tick_cpu_us.p95}, {"max", r.tick_cpu_us.max},
                      {"mean", r.tick_cpu_us.mean}};
  j["us_per_agent"] = r.us_per_agent();
  j["phase_median_us"] = {{"move", r.move_us_median},
                          {"params", r.params_us_median},
                          {"broadphase", r.broadphase_us_median},
                          {"solve", r.solve_us_median},
                          {"driver", r.driver_us_median}};
  j["residual"] = {{"max_pen_over_radius", r.residual.max_pen_over_radius},
                   {"p99_pen_over_radius", r.residual.p99_pen_over_radius},
                   {"pairs_over_1pct", r.residual.pairs_over_1pct},
                   {"pair_tests", r.residual.pair_tests},
                   {"coincident_bodies", r.residual.coincident_bodies}};
  const ResidualOverTime& o = r.residual_over_time;
  j["residual_over_time"] = {{"from_tick", o.from_tick},
                             {"ticks_measured", o.ticks_measured},
                             {"worst_max_pen_over_radius", o.worst_max_pen_over_radius},
                             {"worst_max_tick", o.worst_max_tick},
                             {"worst_p99_pen_over_radius", o.worst_p99_pen_over_radius},
                             {"ticks_over_0_5_r", o.ticks_over_0_5_r}};
  j["static_pen_max_over_radius"] = r.static_pen_max_over_radius;
  j["nan_count"] = r.residual.nan_count;
  j["state_hash"] = hash_hex(r.state_hash);
  j["solver"] = {{"candidate_pairs_median", r.candidate_pairs_median},
                 {"iterations_used_mean", r.iterations_used_mean},
                 {"band_sweeps_skipped_share", r.band_sweeps_skipped_share()},
                 {"pair_list_reused_ticks", r.pair_list_reused_ticks},
                 {"pair_list_searched_ahead_ticks", r.pair_list_searched_ahead_ticks},
                 {"second_search_ticks", r.second_search_ticks},
                 {"capped_bodies_max", r.capped_bodies_max},
                 {"tunnel_clamps_total", r.tunnel_clamps_total},
                 {"max_pen_over_radius_last_tick", r.solver_max_pen_over_radius_last}};
  j["build_s"] = r.build_s;
  j["wall_s"] = r.wall_s;
  return j;
}

}  // namespace throng::bench
