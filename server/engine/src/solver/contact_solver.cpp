#include "solver/contact_solver.h"

#include <algorithm>
#include <cmath>

#include "solver/fast_pair_kernel.h"
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

inline void warm_start_pair(SolverBodies& b, SolverPair& p, const std::vector<SolverPlane>& planes) {
  if (p.lambda == 0.0) return;
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

// warm_start_pair for a fast pair of the schedule (no planes: the pinned share is the exact one,
// which share_now still is before the first sweep). Same operations, same order.
inline void warm_start_fast(const BodyPtrs& b, PairSchedule& s, std::uint32_t f) {
  double lambda = s.lambda[f];
  if (lambda == 0.0) return;
  const std::uint32_t ia = s.a[f], ib = s.b[f];
  lambda = std::min(lambda, kWarmStartCapOverRadius * std::min(b.r[ia], b.r[ib]));
  s.lambda[f] = lambda;
  const double dx = b.x[ib] - b.x[ia], dy = b.y[ib] - b.y[ia];
  const double d = std::sqrt(dx * dx + dy * dy);
  double nx, ny;
  if (d > 1e-9 * (b.r[ia] + b.r[ib])) { nx = dx / d; ny = dy / d; }
  else coincident_direction(b.id[ia], b.id[ib], nx, ny);
  const double move_a = lambda * s.share_now[f];
  const double move_b = lambda - move_a;
  b.x[ia] -= nx * move_a; b.y[ia] -= ny * move_a;
  b.x[ib] += nx * move_b; b.y[ib] += ny * move_b;
}

}  // namespace

void apply_warm_start(SolverBodies& b, std::vector<SolverPair>& pairs, const std::vector<SolverPlane>& planes) {
  for (SolverPair& p : pairs) warm_start_pair(b, p, planes);
}

void apply_warm_start(SolverBodies& bodies, std::vector<SolverPair>& pairs, const std::vector<SolverPlane>& planes,
                      PairSchedule& schedule) {
  const BodyPtrs b(bodies);
  for (const PairSchedule::Level& lv : schedule.levels) {
    for (std::uint32_t f = lv.fast_begin; f < lv.fast_end; ++f) warm_start_fast(b, schedule, f);
    for (std::uint32_t k = lv.slow_begin; k < lv.slow_end; ++k) warm_start_pair(bodies, pairs[schedule.slow[k]], planes);
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
                           std::uint32_t iterations, double converged, double conflict_limit, PairSchedule& schedule,
                           bool scheduled) {
  SolveResult result;
  const BodyPtrs b(bodies);
  double worst = 0.0;
  // Most crowds touch no scenery at all; skip the per-pair pinned test for them.
  const bool any_planes = !planes.empty();
  // Pairs with an airborne body or a body against scenery (see pair_schedule.h), and every pair
  // of an unscheduled solve.
  auto project_slow = [&](SolverPair& p) {
    double share = p.share_a;
    if (p.resolved_once != 0 && conflict_limit > 0.0) share = std::clamp(share, conflict_limit, 1.0 - conflict_limit);
    if (any_planes) share = pinned_share(bodies, planes, p, share);
    const double pen = project_pair(b, p, share);
    if (pen > 0.0) {
      p.resolved_once = 1;
      const double r_min = std::min(b.r[p.a], b.r[p.b]);
      if (pen > worst * r_min) worst = pen / r_min;  // divide only for a new maximum
    }
  };
  auto project_level = [&](const PairSchedule::Level& lv) {
    worst = std::max(worst, project_fast_range(b, schedule, lv.fast_begin, lv.fast_end));
    for (std::uint32_t k = lv.slow_begin; k < lv.slow_end; ++k) project_slow(pairs[schedule.slow[k]]);
  };
  const std::size_t nl = schedule.levels.size();
  for (std::uint32_t it = 0; it < iterations; ++it) {
    worst = 0.0;
    // Without a schedule (see wants_schedule) the pairs' own order, alternating; with one, the
    // levels (pairs of one level share no body, so only the order of the levels matters).
    if (!scheduled && it % 2 == 0) for (SolverPair& p : pairs) project_slow(p);
    else if (!scheduled) for (std::size_t k = pairs.size(); k > 0; --k) project_slow(pairs[k - 1]);
    else if (it % 2 == 0) for (std::size_t l = 0; l < nl; ++l) project_level(schedule.levels[l]);
    else for (std::size_t l = nl; l > 0; --l) project_level(schedule.levels[l - 1]);
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
  if (scheduled) write_back_pair_schedule(schedule, pairs);
  schedule.last_sweeps = result.iterations_used;
  schedule.last_pairs = pairs.size();
  schedule.last_pushing = 0;
  for (const SolverPair& p : pairs) schedule.last_pushing += p.lambda > 0.0 ? 1 : 0;
  return result;
}

}  // namespace throng::detail
