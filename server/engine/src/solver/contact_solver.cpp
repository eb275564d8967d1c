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
                           std::uint32_t iterations, double converged, double conflict_limit, PairSchedule& schedule) {
  SolveResult result;
  const BodyPtrs b(bodies);
  double worst = 0.0;
  // Most crowds touch no scenery at all; skip the per-pair pinned test for them.
  const bool any_planes = !planes.empty();
  // Pairs with an airborne body or a body against scenery (see pair_schedule.h), and every pair
  // of an unscheduled sweep.
  auto project_slow = [&](SolverPair& p) {
    double share = p.share_a;
    if (p.resolved_once != 0 && conflict_limit > 0.0) share = std::clamp(share, conflict_limit, 1.0 - conflict_limit);
    if (any_planes) share = pinned_share(bodies, planes, p, share);
    const double pen = project_pair(b, p, share);
    if (pen > 0.0) {
      p.resolved_once = 1;
      worst = std::max(worst, pen / std::min(b.r[p.a], b.r[p.b]));
    }
  };
  auto project_level = [&](const PairSchedule::Level& lv) {
    worst = std::max(worst, project_fast_range(b, schedule, lv.fast_begin, lv.fast_end));
    for (std::uint32_t k = lv.slow_begin; k < lv.slow_end; ++k) project_slow(pairs[schedule.slow[k]]);
  };
  // Building the schedule costs about two sweeps' worth of time, so a crowd that settled within
  // one sweep last tick (idle bodies, light contact) runs its first sweep in plain pair order —
  // the same result — and gets a schedule only if it needs a second one. This is only a guess
  // about speed: either path gives the same bits.
  bool scheduled = false;
  auto ensure_schedule = [&] {
    if (scheduled) return;
    build_pair_schedule(bodies, pairs, conflict_limit, schedule);
    scheduled = true;
  };
  if (schedule.last_sweeps > 1) ensure_schedule();
  for (std::uint32_t it = 0; it < iterations; ++it) {
    worst = 0.0;
    if (it > 0) ensure_schedule();
    const std::size_t nl = schedule.levels.size();
    // Pairs of one level share no body, so only the order of the levels matters.
    if (!scheduled) for (SolverPair& p : pairs) project_slow(p);
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
  return result;
}

}  // namespace throng::detail
