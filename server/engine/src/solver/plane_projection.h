#pragma once
// Projection of a body out of its fixed-body planes (the patent's FIG. 6c/d: a body touching
// several fixed bodies is pushed out of all their planes). A few passes over the body's planes
// settle corners where two planes meet at an angle.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "solver/solver_data.h"

namespace throng::detail {

// How far below a plane a body may be and still count as resting on it, as a fraction of radius.
inline constexpr double kPinnedSlackOverRadius = 0.02;

inline bool is_pinned(const SolverBodies& b, const std::vector<SolverPlane>& planes, std::uint32_t i, double dx,
                      double dy) {
  const std::uint32_t end = b.plane_begin[i] + b.plane_count[i];
  for (std::uint32_t k = b.plane_begin[i]; k < end; ++k) {
    const SolverPlane& pl = planes[k];
    if (pl.nx * dx + pl.ny * dy > -0.5) continue;  // push does not go into this plane
    const double slack = pl.nx * b.px(i) + pl.ny * b.py(i) + pl.nz * b.z[i] - pl.offset;
    if (slack <= kPinnedSlackOverRadius * b.r[i]) return true;
  }
  return false;
}

// Returns the deepest violation found before projecting.
inline double project_planes(SolverBodies& b, const std::vector<SolverPlane>& planes, std::uint32_t i) {
  constexpr int kPasses = 3;
  double worst = 0.0;
  const std::uint32_t end = b.plane_begin[i] + b.plane_count[i];
  for (int pass = 0; pass < kPasses; ++pass) {
    bool moved = false;
    for (std::uint32_t k = b.plane_begin[i]; k < end; ++k) {
      const SolverPlane& pl = planes[k];
      const double s = pl.nx * b.px(i) + pl.ny * b.py(i) + pl.nz * b.z[i] - pl.offset;
      if (s >= 0.0) continue;
      if (pass == 0) worst = std::max(worst, -s);
      if (b.grounded[i]) {
        // Move in the ground plane only; a plane that is nearly horizontal is a floor, not a wall.
        const double h2 = pl.nx * pl.nx + pl.ny * pl.ny;
        if (h2 < 0.09) continue;
        const double t = -s / h2;
        b.shift(i, pl.nx * t, pl.ny * t);
      } else {
        b.shift(i, -(pl.nx * s), -(pl.ny * s));
        b.z[i] -= pl.nz * s;
      }
      moved = true;
    }
    if (!moved) break;
  }
  return worst;
}

}  // namespace throng::detail
