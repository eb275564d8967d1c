#include "solver/contact_solver.h"

#include <algorithm>
#include <cmath>

#include "solver/pair_projection.h"
#include "solver/plane_projection.h"

namespace throng::detail {
namespace {

// Horizontal unit direction from a to b (or the coincident fallback).
inline void pair_direction(const SolverBodies& b, const SolverPair& p, double& nx, double& ny) {
  const double dx = b.x[p.b] - b.x[p.a], dy = b.y[p.b] - b.y[p.a];
  const double d = std::sqrt(dx * dx + dy * dy);
  if (d > 1e-9 * (b.r[p.a] + b.r[p.b])) { nx = dx / d; ny = dy / d; }
  else coincident_direction(b.id[p.a], b.id[p.b], nx, ny);
}

// A body resting on a fixed plane that faces against the push cannot give way: the other body of
// the pair takes the whole correction. Without this, a body pinned between a wall and a heavy
// pusher would be squeezed into the wall every sweep and pulled back by the plane, converging only
// geometrically with the pusher's (small) share.
inline double pinned_share(const SolverBodies& b, const std::vector<SolverPlane>& planes, const SolverPair& p,
                           double share_a) {
  if ((b.plane_count[p.a] | b.plane_count[p.b]) == 0) return share_a;
  double nx, ny;
  pair_direction(b, p, nx, ny);
  const bool pinned_a = is_pinned(b, planes, p.a, -nx, -ny);
  const bool pinned_b = is_pinned(b, planes, p.b, nx, ny);
  if (pinned_a && !pinned_b) return 0.0;
  if (pinned_b && !pinned_a) return 1.0;
  return share_a;
}

// Warm-start pushes above this fraction of the smaller radius are cut back (see apply_warm_start).
constexpr double kWarmStartCapOverRadius = 0.5;

}  // namespace

void apply_warm_start(SolverBodies& b, std::vector<SolverPair>& pairs, const std::vector<SolverPlane>& planes) {
  for (SolverPair& p : pairs) {
    if (p.lambda == 0.0) continue;
    // Last tick's push is a guess, not a fact: cap it so that a pair whose push kept being undone
    // by something else (a wall) cannot accumulate a push larger than the bodies themselves.
    p.lambda = std::min(p.lambda, kWarmStartCapOverRadius * std::min(b.r[p.a], b.r[p.b]));
    double nx, ny;
    pair_direction(b, p, nx, ny);
    // Same split as the solve itself, including bodies pinned against fixed planes.
    const double move_a = p.lambda * pinned_share(b, planes, p, p.share_a);
    const double move_b = p.lambda - move_a;
    b.x[p.a] -= nx * move_a; b.y[p.a] -= ny * move_a;
    b.x[p.b] += nx * move_b; b.y[p.b] += ny * move_b;
  }
}

void measure_start_depths(const SolverBodies& b, std::vector<SolverPair>& pairs, std::vector<SolverPlane>& planes) {
  for (SolverPair& p : pairs) {
    const double dx = b.x[p.b] - b.x[p.a], dy = b.y[p.b] - b.y[p.a];
    const double gap = std::max(0.0, std::fabs(b.z[p.b] - b.z[p.a]) - b.hh[p.a] - b.hh[p.b]);
    p.depth_start = std::max(0.0, b.r[p.a] + b.r[p.b] - std::sqrt(dx * dx + dy * dy + gap * gap));
  }
  for (SolverPlane& pl : planes) {
    const std::uint32_t i = pl.body;
    pl.depth_start = std::max(0.0, pl.offset - (pl.nx * b.x[i] + pl.ny * b.y[i] + pl.nz * b.z[i]));
  }
}

SolveResult solve_contacts(SolverBodies& bodies, std::vector<SolverPair>& pairs, const std::vector<SolverPlane>& planes,
                           std::uint32_t iterations, double converged, double conflict_limit) {
  SolveResult result;
  const BodyPtrs b(bodies);
  const std::size_t np = pairs.size();
  double worst = 0.0;
  // Most crowds touch no scenery at all; skip the per-pair pinned test for them.
  const bool any_planes = !planes.empty();
  auto project = [&](SolverPair& p) {
    double share = p.share_a;
    if (p.resolved_once != 0 && conflict_limit > 0.0) share = std::clamp(share, conflict_limit, 1.0 - conflict_limit);
    if (any_planes) share = pinned_share(bodies, planes, p, share);
    const double pen = project_pair(b, p, share);
    if (pen > 0.0) p.resolved_once = 1;
    if (pen > 0.0) {
      const double r_min = std::min(b.r[p.a], b.r[p.b]);
      if (pen > worst * r_min) worst = pen / r_min;  // divide only for a new maximum
    }
  };
  for (std::uint32_t it = 0; it < iterations; ++it) {
    worst = 0.0;
    if (it % 2 == 0) for (std::size_t k = 0; k < np; ++k) project(pairs[k]);
    else for (std::size_t k = np; k > 0; --k) project(pairs[k - 1]);
    // Fixed bodies last in every sweep: they always win, and the final state honours them exactly.
    for (std::size_t i = 0; any_planes && i < bodies.size(); ++i) {
      if (bodies.plane_count[i] == 0) continue;
      const double pen = project_planes(bodies, planes, static_cast<std::uint32_t>(i));
      if (pen > 0.0) worst = std::max(worst, pen / bodies.r[i]);
    }
    result.iterations_used = it + 1;
    result.max_pen_over_radius = worst;
    if (worst <= converged) break;
  }
  return result;
}

}  // namespace throng::detail
