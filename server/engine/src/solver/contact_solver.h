#pragma once
// The iterative projection solver (the patent's extrusion process, FIG. 9 steps S7-S11, repeated):
// every overlapping pair is pushed apart at its share point and every body is pushed out of all its
// fixed-body planes, sweep after sweep, until nothing intrudes or the iteration budget ends.
#include <cstdint>
#include <vector>

#include "solver/solver_data.h"

namespace throng::detail {

struct SolveResult {
  std::uint32_t iterations_used = 0;
  double max_pen_over_radius = 0.0;  // deepest pair or plane seen in the last sweep
};

// Applies each pair's warm-start push (pair.lambda from the previous tick) along the current normal.
void apply_warm_start(SolverBodies& bodies, std::vector<SolverPair>& pairs, const std::vector<SolverPlane>& planes);

// Records each pair's and plane's penetration at the start of the solve (for push events).
void measure_start_depths(const SolverBodies& bodies, std::vector<SolverPair>& pairs, std::vector<SolverPlane>& planes);

// Sweeps cycle through four orders of the pairs: rows up / cells right, rows down / cells left,
// rows up / cells left, rows down / cells right (the "fast sweeping" idea from eikonal solvers).
// A Gauss-Seidel sweep carries a push far along its own order but only one contact against it, so
// in a crowd pressing from all sides each quadrant's pressure gets a sweep in its own direction
// every four iterations. row_starts comes from the broadphase (pair index of each cell row, then
// the end of the rows); pairs after the last row (coarser levels) are swept in list order.
SolveResult solve_contacts(SolverBodies& bodies, std::vector<SolverPair>& pairs, const std::vector<SolverPlane>& planes,
                           const std::vector<std::uint32_t>& row_starts, std::uint32_t iterations,
                           double converged_pen_over_radius);

}  // namespace throng::detail
