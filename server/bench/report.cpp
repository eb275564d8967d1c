#include "report.h"

#include <fmt/core.h>

namespace throng::bench {

void print_summary(std::FILE* out, const RunResult& r) {
  fmt::print(out, "scene      {} ({} agents, {} ticks after {} warmup, {} iterations, {} thread{})\n", r.scene, r.agents,
             r.ticks, r.warmup, r.iterations, r.threads, r.threads == 1 ? "" : "s");
  fmt::print(out, "tick       median {:.0f} us, p95 {:.0f} us, max {:.0f} us ({:.3f} us per agent)\n", r.tick_us.median,
             r.tick_us.p95, r.tick_us.max, r.us_per_agent());
  fmt::print(out, "tick cpu   median {:.0f} us, p95 {:.0f} us (thread CPU time: not inflated by waiting for a core)\n",
             r.tick_cpu_us.median, r.tick_cpu_us.p95);
  fmt::print(out, "phases     move {:.0f}, params {:.0f}, broadphase {:.0f}, solve {:.0f} us (medians); driver {:.0f} us\n",
             r.move_us_median, r.params_us_median, r.broadphase_us_median, r.solve_us_median, r.driver_us_median);
  fmt::print(out, "solver     {:.0f} candidate pairs (median), {:.2f} iterations used (mean), {:.0f}% of band sweeps "
                  "left out as calm, {} ticks kept the pair list ({} began the next one's search), {} searched again, {} capped bodies (max), {} tunnel clamps, own max pen/r {:.4g}\n",
             r.candidate_pairs_median, r.iterations_used_mean, 100.0 * r.band_sweeps_skipped_share(), r.pair_list_reused_ticks,
             r.pair_list_searched_ahead_ticks, r.second_search_ticks, r.capped_bodies_max,
             r.tunnel_clamps_total, r.solver_max_pen_over_radius_last);
  fmt::print(out, "residual   max pen/r {:.4g}, p99 pen/r {:.4g}, {} pairs over 1% (independent check, {} pair tests)\n",
             r.residual.max_pen_over_radius, r.residual.p99_pen_over_radius, r.residual.pairs_over_1pct,
             r.residual.pair_tests);
  const ResidualOverTime& o = r.residual_over_time;
  if (o.ticks_measured > 0)
    fmt::print(out, "worst tick max pen/r {:.4g} (tick {}), worst p99 pen/r {:.4g}, {} ticks over 0.5 r (ticks {}..{})\n",
               o.worst_max_pen_over_radius, o.worst_max_tick, o.worst_p99_pen_over_radius, o.ticks_over_0_5_r, o.from_tick,
               o.from_tick + o.ticks_measured - 1);
  fmt::print(out, "scenery    max pen/r {:.4g}\n", r.static_pen_max_over_radius);
  fmt::print(out, "nan        {}\n", r.residual.nan_count);
  fmt::print(out, "hash       {}\n", hash_hex(r.state_hash));
  fmt::print(out, "time       build {:.2f} s, run {:.2f} s\n", r.build_s, r.wall_s);
}

}  // namespace throng::bench
