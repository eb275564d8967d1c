#pragma once
// The iterative projection solver (the patent's extrusion process, FIG. 9 steps S7-S11, repeated):
// every overlapping pair is pushed apart at its share point and every body is pushed out of all its
// fixed-body planes, sweep after sweep, until nothing intrudes or the iteration budget ends.
#include <cstdint>
#include <vector>

#include "solver/pair_schedule.h"
#include "solver/solver_data.h"

namespace throng::detail {

struct SolveResult {
  std::uint32_t iterations_used = 0;
  double max_pen_over_radius = 0.0;  // deepest pair or plane seen in the last sweep
};

// Applies each pair's warm-start push (pair.lambda from the previous tick) along the current normal.
void apply_warm_start(SolverBodies& bodies, std::vector<SolverPair>& pairs, const std::vector<SolverPlane>& planes);
// The same in the schedule's level order (same bits, without each pair waiting on the previous
// one); the fast pairs' lambda is then the schedule's copy.
void apply_warm_start(SolverBodies& bodies, std::vector<SolverPair>& pairs, const std::vector<SolverPlane>& planes,
                      PairSchedule& schedule);

// Building the schedule costs about two sweeps' worth of time, so a crowd that settled within one
// sweep last tick (idle bodies, light contact) goes without one until it needs a second sweep.
// Nor does a crowd where most candidate pairs are apart (battle: 5% pushing, street 20%): the
// plain order skips those pairs in a few instructions and has few store-to-load chains, while the
// two-lane kernel computes every pair (battle's solve was 26% more instructions with it).
// Crush and mixed push in 77-82% of their pairs. Only a guess about speed: either path gives the
// same bits.
inline bool wants_schedule(const PairSchedule& schedule) {
  return schedule.last_sweeps > 1 && 3 * schedule.last_pushing >= schedule.last_pairs;
}

// Records each pair's and plane's penetration at the start of the solve (for push events).
void measure_start_depths(const SolverBodies& bodies, std::vector<SolverPair>& pairs, std::vector<SolverPlane>& planes);

// Sweeps alternate direction (symmetric Gauss-Seidel): a sweep carries a push far along its own
// order but only one contact against it, so alternating lets pressure travel both ways through a
// packed crowd. (Cycling four row/column orders, as fast-sweeping eikonal solvers do, was measured
// worse on the crush scene at 8 and 16 iterations: p99 0.115 vs 0.070 at K = 8.)
// conflict_share_limit > 0 clamps the share of every push after a pair's first one in a tick into
// [limit, 1 - limit] (see WorldSettings::conflict_share_limit); 0 keeps the exact share throughout.
// The sweeps visit the pairs in the level order of pair_schedule.h (same result as the pairs' own
// order, without the wait on each previous projection); `schedule` is reused scratch, already
// built for these pairs if `scheduled`.
SolveResult solve_contacts(SolverBodies& bodies, std::vector<SolverPair>& pairs, const std::vector<SolverPlane>& planes,
                           std::uint32_t iterations, double converged_pen_over_radius, double conflict_share_limit,
                           PairSchedule& schedule, bool scheduled);

}  // namespace throng::detail
