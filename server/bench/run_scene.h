#pragma once
// Runs one scene headless and collects what the bench reports: per-tick timings from StepStats;
// the independent residual metric every tick from residual_from on (a player sees every tick, not
// only the last), measured outside the timed step; and after the last tick the residual again,
// the state hash and NaN count.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "throng/scene/residual.h"
#include "throng/scene/scene_def.h"

namespace throng::bench {

struct RunOptions {
  std::uint64_t ticks = 0;   // measured ticks
  std::uint64_t warmup = 0;  // ticks run first and left out of the timing statistics
  bool progress = true;      // progress lines on stderr for long runs
  // First tick (counted from 1, warm-up included) whose residual is measured; 0 = only after the
  // last tick. The default leaves out the first two seconds of a crowd converging.
  std::uint64_t residual_from = 61;
  std::string trace_path;    // non-empty: one CSV line per tick (trace_header() names the columns)
};

// The worst tick, not the last: over every tick from RunOptions::residual_from.
struct ResidualOverTime {
  std::uint64_t from_tick = 0;
  std::uint64_t ticks_measured = 0;
  double worst_max_pen_over_radius = 0.0;
  std::uint64_t worst_max_tick = 0;  // the tick that had it
  double worst_p99_pen_over_radius = 0.0;
  std::uint64_t ticks_over_0_5_r = 0;  // ticks whose max pen/r exceeded 0.5
};

// The CSV columns --trace writes.
inline constexpr const char* kTraceHeader =
    "tick,tick_us,max_pen_over_radius,p99_pen_over_radius,pairs_over_1pct,solver_max_pen_over_radius,iterations_used,"
    "tunnel_clamps,search_us,solve_us,searched,second_search,searched_ahead";

struct Percentiles {
  double median = 0.0;
  double p95 = 0.0;
  double max = 0.0;
  double mean = 0.0;
};

struct RunResult {
  std::string scene;
  std::uint64_t agents = 0;
  std::uint64_t ticks = 0;
  std::uint64_t warmup = 0;
  std::uint32_t iterations = 0;
  std::uint32_t threads = 1;
  Percentiles tick_us;        // StepStats.total_us over the measured ticks
  // The same World::step() timed with the thread's CPU clock: on a shared build machine the wall
  // clock also counts the time the thread waited for a core, which inflates medians several-fold.
  Percentiles tick_cpu_us;
  double move_us_median = 0.0;
  double params_us_median = 0.0;
  double broadphase_us_median = 0.0;
  double solve_us_median = 0.0;
  double driver_us_median = 0.0;  // the bench's SceneDriver, outside World::step
  double candidate_pairs_median = 0.0;
  double iterations_used_mean = 0.0;
  std::uint64_t band_sweeps_total = 0;          // scheduled solve: bands x sweeps over the run
  std::uint64_t band_sweeps_skipped_total = 0;  // of which left out as calm
  double band_sweeps_skipped_share() const {
    return band_sweeps_total == 0 ? 0.0 : static_cast<double>(band_sweeps_skipped_total) / static_cast<double>(band_sweeps_total);
  }
  std::uint64_t pair_list_reused_ticks = 0;     // ticks that kept the pair list (no search)
  std::uint64_t pair_list_searched_ahead_ticks = 0;  // ticks that ended by beginning the next list's search
  std::uint64_t second_search_ticks = 0;        // ticks that searched again after the solve
  std::uint64_t capped_bodies_max = 0;
  std::uint64_t tunnel_clamps_total = 0;
  double solver_max_pen_over_radius_last = 0.0;  // the solver's own figure, for comparison
  scene::ResidualStats residual;  // after the last tick
  ResidualOverTime residual_over_time;
  double static_pen_max_over_radius = 0.0;
  std::uint64_t state_hash = 0;
  double build_s = 0.0;
  double wall_s = 0.0;

  double us_per_agent() const { return agents ? tick_us.median / double(agents) : 0.0; }
};

RunResult run_scene(const scene::SceneDef& scene, const RunOptions& options);

// Nearest-rank percentile (q in [0, 1]) of values; 0 for an empty input.
double percentile(std::vector<double> values, double q);
Percentiles summarize(const std::vector<double>& values);

nlohmann::ordered_json to_json(const RunResult& r);
std::string hash_hex(std::uint64_t h);

}  // namespace throng::bench
