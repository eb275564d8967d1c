#pragma once
// The iterative projection solver (the patent's extrusion process, FIG. 9 steps S7-S11, repeated):
// every overlapping pair is pushed apart at its share point and every body is pushed out of all its
// fixed-body planes, sweep after sweep, until nothing intrudes or the iteration budget ends.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "solver/pair_schedule.h"
#include "solver/solver_data.h"

namespace throng {
class WorkerPool;
}

namespace throng::detail {

struct SolveResult {
  std::uint32_t iterations_used = 0;
  double max_pen_over_radius = 0.0;  // deepest pair or plane seen in the last sweep
  // Scheduled solve: bands times sweeps, and how many of those band visits were left out as calm.
  std::uint32_t band_sweeps = 0;
  std::uint32_t band_sweeps_skipped = 0;
};

// Marks the pairs that start the solve held by their neighbours (held_by_neighbours in
// pair_schedule.h) as already pushed once (SolverPair::resolved_once), so that their warm start and
// every push take the conflict share. With a schedule only its slow pairs: the schedule marks its
// fast pairs itself when it is built. Call before the warm start; a no-op when the limit is off.
void mark_held_pairs(const SolverBodies& bodies, std::vector<SolverPair>& pairs, const PairSchedule* schedule,
                     double conflict_share_limit);

// Applies each pair's warm-start push (pair.lambda from the previous tick) along the current normal,
// then cuts every body's net warm-start move to kWarmStartMoveCapOverRadius of its radius (see
// there). A pair marked by mark_held_pairs moves its bodies at the conflict share.
void apply_warm_start(SolverBodies& bodies, std::vector<SolverPair>& pairs, const std::vector<SolverPlane>& planes,
                      double conflict_share_limit);
// The same for a scheduled solve, in the order of its forward sweep (for_each_block: the blocks of a
// phase on the pool's threads, the same bits for any number), on the float displacements; the
// fast pairs' lambda is then the schedule's copy.
void apply_warm_start(SolverBodies& bodies, std::vector<SolverPair>& pairs, const std::vector<SolverPlane>& planes,
                      PairSchedule& schedule, double conflict_share_limit, WorkerPool* pool = nullptr);

// Which of the two solves a tick gets (see solve_contacts). It changes the bits (the scheduled
// solve carries displacements in float), so it is a function of the saved state only: the pair
// count and how many pairs start with a warm-start push (last tick's pushes, kept in checkpoints),
// never of timing or of what an earlier tick in this process happened to see.
// Speed: building the schedule costs about two sweeps' worth of time, and a crowd where most
// candidate pairs are apart (a battle's lines, a street) is faster in pair order, where a
// separated pair is skipped in a few instructions; a crush pushes in most of its pairs.
// Small scenes stay in the exact double-precision order (the patent examples are exact to 1e-12).
inline constexpr std::size_t kMinScheduledPairs = 256;
inline bool wants_schedule(std::size_t pair_count, std::size_t warm_pairs) {
  return pair_count >= kMinScheduledPairs && 3 * warm_pairs >= pair_count;
}

// Penetration of the upright capsules of bodies a and c with horizontal separation (dx, dy).
inline double depth_at(const SolverBodies& b, std::uint32_t a, std::uint32_t c, double dx, double dy) {
  const double gap = std::max(0.0, std::fabs(b.z[c] - b.z[a]) - b.hh[a] - b.hh[c]);
  return std::max(0.0, b.r[a] + b.r[c] - std::sqrt(dx * dx + dy * dy + gap * gap));
}

// Penetration of a pair at the bodies' current positions (3D distance of the core segments).
double pair_depth(const SolverBodies& bodies, const SolverPair& pair);

// Records each pair's and plane's penetration before the warm start (for push events). With a
// schedule, only its slow pairs: a fast pair's start depth is still there after a scheduled solve
// (fast_pair_start_depth), so it is computed only for the pairs that end up pushing.
void measure_start_depths(const SolverBodies& bodies, std::vector<SolverPair>& pairs, std::vector<SolverPlane>& planes,
                          const PairSchedule* schedule);

// Fast pair f's depth at the start of a scheduled solve, read after it from the schedule (the start
// distance is target - pen0) and the bodies' heights (grounded bodies never change height).
// Inline: the warm-start store calls it for every pushing pair (as a call it showed in profiles).
inline double fast_pair_start_depth(const SolverBodies& bodies, const PairSchedule& schedule, std::uint32_t f) {
  return depth_at(bodies, schedule.a[f], schedule.b[f],
                  static_cast<double>(schedule.target[f]) - static_cast<double>(schedule.pen0[f]), 0.0);
}

// Sweeps alternate direction (symmetric Gauss-Seidel): a sweep carries a push far along its own
// order but only one contact against it, so alternating lets pressure travel both ways through a
// packed crowd. (Cycling four row/column orders, as fast-sweeping eikonal solvers do, was measured
// worse on the crush scene at 8 and 16 iterations: docs/design/solver.md.)
// conflict_share_limit > 0 clamps the share of every push after a pair's first one in a tick into
// [limit, 1 - limit] (see WorldSettings::conflict_share_limit); 0 keeps the exact share throughout.
// Unscheduled, the sweeps visit the pairs in their own order, moving the double positions. Scheduled
// (`schedule` built for these pairs, bodies.displaced set), they visit the bands of pair_schedule.h
// block by block, phase by phase (PairSchedule::block_band): within a block every body's pairs
// keep their relative order and no projection waits for the previous one; blocks of one phase
// share no body. They move the bodies' float displacements (SolverBodies::u). The fast pairs'
// pushes are then in schedule.lambda (write_back_pair_schedule copies them into `pairs`); the slow
// pairs' are in `pairs`. With a pool, the blocks of a phase are shared among its threads: the same
// bits as without one, for any number of threads.
SolveResult solve_contacts(SolverBodies& bodies, std::vector<SolverPair>& pairs, const std::vector<SolverPlane>& planes,
                           std::uint32_t iterations, std::uint32_t extra_iterations, double converged_pen_over_radius,
                           double conflict_share_limit, PairSchedule& schedule, bool scheduled,
                           WorkerPool* pool = nullptr);

}  // namespace throng::detail
