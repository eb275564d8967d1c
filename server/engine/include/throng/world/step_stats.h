#pragma once
// What one tick did: phase timings and solver figures, as plain numbers for logs, metrics and the
// bench. Timings are measured with a steady clock and never feed back into the simulation.
#include <cstdint>

namespace throng {

struct StepStats {
  std::uint64_t tick = 0;
  double move_us = 0.0;
  double params_us = 0.0;
  double broadphase_us = 0.0;
  double solve_us = 0.0;
  double total_us = 0.0;
  std::uint32_t candidate_pairs = 0;   // pairs within r_a + r_b + margin
  // 1 when this tick took its pairs from a pair list kept from an earlier tick instead of searching
  // (WorldSettings::pair_list_skin_m), else 0. The first tick after a restore that carried a kept
  // list reads 1 as the saved world would, though it searched the list again.
  std::uint32_t pair_list_reused = 0;
  // 1 when this step ended by beginning the next pair list's search, the kept list being about to be
  // outrun: in two parts when the next tick's check would find it outrun (the next tick finishes
  // the search and, unless its bodies outran that list too or its search was capped, reads
  // pair_list_reused = 1), in three when the check after it would (the kept list serves the next
  // tick, whose end finishes the scan: pair_list_ahead_finished; the tick after takes the list).
  std::uint32_t pair_list_searched_ahead = 0;
  // 1 when this step ended by finishing the scan of a search the last step began in three parts
  // (its kept list ended with this step).
  std::uint32_t pair_list_ahead_finished = 0;
  std::uint32_t scenery_planes = 0;    // body-vs-fixed separating planes built this tick
  std::uint32_t iterations_used = 0;
  std::uint32_t capped_bodies = 0;     // bodies that hit max_candidates_per_body
  std::uint32_t tunnel_clamps = 0;     // fast moves shortened by the swept test
  // 1 when the solve moved a body further than the contact margin and the tick searched again and
  // went on solving with the pairs found there (World::step).
  std::uint32_t second_search = 0;
  std::uint32_t pile_relief_bodies = 0;  // bodies laid out afresh from a degenerate pile
  // Deepest pair or plane met during the last sweep, before that sweep's own corrections (so it
  // reads higher than an after-tick measurement; throng-bench reports both).
  double max_pen_over_radius = 0.0;
  // Scheduled (crowd) solve: schedule bands times sweeps, and the band visits left out because
  // nothing near them changed a push (see kCalmPushOverRadius in the solver). Both 0 otherwise.
  std::uint32_t band_sweeps = 0;
  std::uint32_t band_sweeps_skipped = 0;
};

}  // namespace throng
