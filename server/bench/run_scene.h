#pragma once
// Runs one scene headless and collects what the bench reports: per-tick timings from StepStats,
// then, after the last tick, the independent residual metrics, the state hash and NaN count.
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
};

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
  std::uint64_t capped_bodies_max = 0;
  std::uint64_t tunnel_clamps_total = 0;
  double solver_max_pen_over_radius_last = 0.0;  // the solver's own figure, for comparison
  scene::ResidualStats residual;
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
