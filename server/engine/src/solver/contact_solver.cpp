#include "solver/contact_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "solver/fast_pair_kernel.h"
#include "solver/pair_projection.h"
#include "solver/plane_projection.h"
#include "throng/core/worker_pool.h"

namespace throng::detail {
namespace {

// Horizontal unit direction from a to b (or the coincident fallback).
inline void pair_direction(const SolverBodies& b, const SolverPair& p, double& nx, double& ny) {
  const double dx = b.px(p.b) - b.px(p.a), dy = b.py(p.b) - b.py(p.a);
  const double d = std::sqrt(dx * dx + dy * dy);
  if (d > 1e-9 * (b.r[p.a] + b.r[p.b])) { nx = dx / d; ny = dy / d; }
  else coincident_direction(b.id[p.a], b.id[p.b], nx, ny);
}

// A body resting on a fixed plane that faces against the push takes at most the smaller of the
// pair's two shares. Why: a light body between a wall and a heavy pusher would otherwise take
// nearly all of every push, be squeezed into the wall each sweep and pulled back by the plane,
// converging only geometrically with the pusher's (small) share; with the smaller share it stays
// put (exactly, in WorldHardCases.AgentPinnedBetweenWallAndHeavyPusher). Why not none at all (the
// rule until it was measured against jams at fixed bodies): with equal weights a pinned body then
// never slides round the pillar it rests on, so a pocket between pillars that holds one body too
// many stays overfull; taking its half, it gives way along the pillar.
inline double pinned_share(const SolverBodies& b, const std::vector<SolverPlane>& planes, const SolverPair& p,
                           double share_a) {
  if ((b.plane_count[p.a] | b.plane_count[p.b]) == 0) return share_a;
  double nx, ny;
  pair_direction(b, p, nx, ny);
  const bool pinned_a = is_pinned(b, planes, p.a, -nx, -ny);
  const bool pinned_b = is_pinned(b, planes, p.b, nx, ny);
  if (pinned_a && !pinned_b) return std::min(share_a, 1.0 - share_a);
  if (pinned_b && !pinned_a) return std::max(share_a, 1.0 - share_a);
  return share_a;
}

// The share a pair's next push moves body a by: its exact share until its first push (or from the
// start when it is held by its neighbours), then the conflict share.
inline double push_share(const SolverPair& p, double conflict_limit) {
  return p.resolved_once != 0 && conflict_limit > 0.0 ? std::clamp(p.share_a, conflict_limit, 1.0 - conflict_limit)
                                                      : p.share_a;
}

inline void warm_start_pair(SolverBodies& b, SolverPair& p, const std::vector<SolverPlane>& planes,
                            double conflict_limit) {
  if (p.lambda == 0.0) return;
  // Last tick's push is a guess, not a fact: cap it so that a pair whose push kept being undone
  // by something else (a wall) cannot accumulate a push larger than the bodies themselves.
  p.lambda = std::min(p.lambda, kWarmStartCapOverRadius * std::min(b.r[p.a], b.r[p.b]));
  double nx, ny;
  pair_direction(b, p, nx, ny);
  // Same split as the solve itself, including bodies pinned against fixed planes.
  const double move_a = p.lambda * pinned_share(b, planes, p, push_share(p, conflict_limit));
  const double move_b = p.lambda - move_a;
  b.shift(p.a, -(nx * move_a), -(ny * move_a));
  b.shift(p.b, nx * move_b, ny * move_b);
}

// Cuts a body's move (dx, dy) to kWarmStartMoveCapOverRadius of its radius; returns the factor.
inline double move_cut(double dx, double dy, double r) {
  const double cap = kWarmStartMoveCapOverRadius * r;
  const double len2 = dx * dx + dy * dy;
  return len2 > cap * cap ? cap / std::sqrt(len2) : 1.0;
}

}  // namespace

void mark_held_pairs(const SolverBodies& b, std::vector<SolverPair>& pairs, const PairSchedule* schedule,
                     double conflict_limit) {
  if (conflict_limit <= 0.0) return;
  auto mark = [&](SolverPair& p) {
    const double r_min = std::min(b.r[p.a], b.r[p.b]);
    // The push the warm start will apply (warm_start_pair's cap), against the depth before it. A
    // push within the margin cannot be held whatever the depth: no distance to compute.
    const double carried = std::min(p.lambda, kWarmStartCapOverRadius * r_min);
    if (carried <= kHeldPushMarginOverRadius * r_min) return;
    if (held_by_neighbours(carried, pair_depth(b, p), 1.0 / r_min)) p.resolved_once = 1;
  };
  if (schedule != nullptr) {
    for (const std::uint32_t k : schedule->slow) mark(pairs[k]);
  } else {
    for (SolverPair& p : pairs) mark(p);
  }
}

void apply_warm_start(SolverBodies& b, std::vector<SolverPair>& pairs, const std::vector<SolverPlane>& planes,
                      double conflict_limit) {
  // Positions move directly here (no displacement array): keep where the bodies started.
  const std::size_t n = b.size();
  std::copy(b.x.begin(), b.x.end(), b.warm_x0.begin());
  std::copy(b.y.begin(), b.y.end(), b.warm_y0.begin());
  for (SolverPair& p : pairs) warm_start_pair(b, p, planes, conflict_limit);
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = b.x[i] - b.warm_x0[i], dy = b.y[i] - b.warm_y0[i];
    const double f = move_cut(dx, dy, b.r[i]);
    if (f < 1.0) {
      b.x[i] = b.warm_x0[i] + dx * f;
      b.y[i] = b.warm_y0[i] + dy * f;
    }
  }
}

void apply_warm_start(SolverBodies& bodies, std::vector<SolverPair>& pairs, const std::vector<SolverPlane>& planes,
                      PairSchedule& schedule, double conflict_limit, WorkerPool* pool) {
  bodies.ensure_pad_slots(schedule.band_count());
  const BodyPtrs b(bodies);
  // In the sweep's forward order (block by block, phase by phase; see for_each_block).
  for_each_block(schedule, pool, true, [&](std::uint32_t k) {
    const std::uint32_t l0 = schedule.band_level[schedule.block_band[k]];
    const std::uint32_t l1 = schedule.band_level[schedule.block_band[k + 1]];
    for (std::uint32_t l = l0; l < l1; ++l) {
      const PairSchedule::Level& lv = schedule.levels[l];
      warm_start_fast_range(b, schedule, lv.fast_begin, lv.fast_end);
      for (std::uint32_t j = lv.slow_begin; j < lv.slow_end; ++j) warm_start_pair(bodies, pairs[schedule.slow[j]], planes, conflict_limit);
    }
  });
  // The displacements start at zero, so u is the warm start's move. Each body on its own: shared
  // out in fixed ranges.
  float* u = bodies.u.data();
  const std::size_t n = bodies.size();
  constexpr std::size_t kBodiesPerTask = 8192;
  auto cut = [&](std::uint32_t t) {
    const std::size_t end = std::min(n, (t + 1) * kBodiesPerTask);
    for (std::size_t i = t * kBodiesPerTask; i < end; ++i) {
      const double dx = u[2 * i], dy = u[2 * i + 1];
      const double f = move_cut(dx, dy, bodies.r[i]);
      if (f < 1.0) {
        u[2 * i] = static_cast<float>(dx * f);
        u[2 * i + 1] = static_cast<float>(dy * f);
      }
    }
  };
  const auto tasks = static_cast<std::uint32_t>((n + kBodiesPerTask - 1) / kBodiesPerTask);
  run_tasks(pool, tasks, cut);
}

double pair_depth(const SolverBodies& b, const SolverPair& p) {
  return depth_at(b, p.a, p.b, b.px(p.b) - b.px(p.a), b.py(p.b) - b.py(p.a));
}

void measure_start_depths(const SolverBodies& b, std::vector<SolverPair>& pairs, std::vector<SolverPlane>& planes,
                          const PairSchedule* schedule) {
  if (schedule != nullptr) {
    for (const std::uint32_t k : schedule->slow) pairs[k].depth_start = pair_depth(b, pairs[k]);
  } else {
    for (SolverPair& p : pairs) p.depth_start = pair_depth(b, p);
  }
  for (SolverPlane& pl : planes) {
    const std::uint32_t i = pl.body;
    pl.depth_start = std::max(0.0, pl.offset - (pl.nx * b.px(i) + pl.ny * b.py(i) + pl.nz * b.z[i]));
  }
}

SolveResult solve_contacts(SolverBodies& bodies, std::vector<SolverPair>& pairs, const std::vector<SolverPlane>& planes,
                           std::uint32_t iterations, std::uint32_t extra_iterations, double converged,
                           double conflict_limit, PairSchedule& schedule, bool scheduled, WorkerPool* pool) {
  SolveResult result;
  if (scheduled) bodies.ensure_pad_slots(schedule.band_count());
  const BodyPtrs b(bodies);
  double worst = 0.0;
  // Most crowds touch no scenery at all; skip the per-pair pinned test for them.
  const bool any_planes = !planes.empty();
  // Pairs with an airborne body or a body against scenery (see pair_schedule.h), and every pair
  // of an unscheduled solve. `worst` is the caller's: a block's own when blocks run side by side.
  auto project_slow = [&](SolverPair& p, double& deepest) {
    double share = push_share(p, conflict_limit);
    if (any_planes) share = pinned_share(bodies, planes, p, share);
    const double pen = project_pair(b, p, share);
    if (pen > 0.0) {
      p.resolved_once = 1;
      const double r_min = std::min(b.r[p.a], b.r[p.b]);
      if (pen > deepest * r_min) deepest = pen / r_min;  // divide only for a new maximum
    }
  };
  // Scheduled: a sweep visits the bands of pair_schedule.h block by block (sweep_scheduled), each
  // band's levels in order (or in reverse). A band's deepest pair goes to `deepest`; its activity is the largest change of push (push or pull) it made in the sweep, over the
  // smaller radius: a band whose pairs only gave back pushes moved its bodies too.
  auto project_band = [&](std::size_t c, bool forward, double& deepest) {
    float moved = 0.0f;
    auto project_level = [&](const PairSchedule::Level& lv) {
      deepest = std::max(deepest, static_cast<double>(project_fast_range(b, schedule, lv.fast_begin, lv.fast_end, moved)));
      for (std::uint32_t k = lv.slow_begin; k < lv.slow_end; ++k) {
        SolverPair& p = pairs[schedule.slow[k]];
        const double lambda_before = p.lambda;
        project_slow(p, deepest);
        moved = std::max(moved, static_cast<float>(std::fabs(p.lambda - lambda_before) / std::min(b.r[p.a], b.r[p.b])));
      }
    };
    const std::uint32_t l0 = schedule.band_level[c], l1 = schedule.band_level[c + 1];
    if (l0 == l1) {
      schedule.band_activity[c] = 0.0f;
      return;
    }
    const PairSchedule::Level& first = schedule.levels[l0];
    const PairSchedule::Level& last = schedule.levels[l1 - 1];
    if (first.slow_begin == last.slow_end) {
      // No slow pair in the band (a crowd's common case): its fast pairs in one span, the levels'
      // padded ranges back to back (one call per band instead of one per level of ~25 pairs).
      const float w = forward ? project_fast_span<false>(b, schedule, first.fast_begin, last.fast_end, moved)
                              : project_fast_span<true>(b, schedule, first.fast_begin, last.fast_end, moved);
      deepest = std::max(deepest, static_cast<double>(w));
    } else if (forward) {
      for (std::uint32_t l = l0; l < l1; ++l) project_level(schedule.levels[l]);
    } else {
      for (std::uint32_t l = l1; l > l0; --l) project_level(schedule.levels[l - 1]);
    }
    schedule.band_activity[c] = moved;
  };
  // One block's bands (pair_schedule.h, PairSchedule::block_band), in order or in reverse; its
  // deepest pair goes to block_worst, as blocks of one phase may run on several threads.
  auto sweep_block = [&](std::uint32_t k, bool forward) {
    double block_worst = 0.0;
    const std::uint32_t c0 = schedule.block_band[k], c1 = schedule.block_band[k + 1];
    if (forward) {
      for (std::uint32_t c = c0; c < c1; ++c) if (schedule.band_swept[c]) project_band(c, true, block_worst);
    } else {
      for (std::uint32_t c = c1; c > c0; --c) if (schedule.band_swept[c - 1]) project_band(c - 1, false, block_worst);
    }
    schedule.block_worst[k] = block_worst;
  };
  auto sweep_scheduled = [&](bool forward) {
    for_each_block(schedule, pool, forward, [&](std::uint32_t k) { sweep_block(k, forward); });
    // The largest of the blocks' maxima: the same whichever thread swept which block.
    for (const double w : schedule.block_worst) worst = std::max(worst, w);
  };
  const std::size_t nb = scheduled ? schedule.band_count() : 0;
  // Calm bands are left out once the pressure has had kFullSweeps sweeps to spread (see
  // kCalmPushOverRadius); with scenery every sweep visits every band, as plane projections move
  // bodies outside any band's record.
  const float calm = schedule.calm_push_over_radius;
  const bool skip_calm = scheduled && !any_planes && calm > 0.0f;
  if (scheduled) {
    // resize + fill: assign past the capacity would reallocate to the exact size (see
    // pair_schedule_build.h).
    schedule.band_activity.resize(nb);
    std::fill(schedule.band_activity.begin(), schedule.band_activity.end(), std::numeric_limits<float>::infinity());
    schedule.band_swept.resize(nb);
    std::fill(schedule.band_swept.begin(), schedule.band_swept.end(), std::uint8_t{1});
  }
  const std::uint32_t most = iterations + extra_iterations;
  for (std::uint32_t it = 0; it < most; ++it) {
    worst = 0.0;
    if (skip_calm && it >= kFullSweeps) {
      // Every band calm: a sweep would change no push by `calm` or more anywhere. The solve stops
      // there, and result keeps the last sweep that ran (so with the default settings a crowd
      // solve stops at 1e-3 r of change per sweep, before converged_pen_over_radius would stop it).
      const std::uint32_t skipped = schedule.choose_bands(calm);
      if (skipped == nb) break;
      result.band_sweeps_skipped += skipped;
    }
    result.band_sweeps += static_cast<std::uint32_t>(nb);
    // Without a schedule (see wants_schedule) the pairs' own order, alternating; with one, the
    // levels (pairs of one level share no body, so only the order of the levels matters).
    if (!scheduled && it % 2 == 0) for (SolverPair& p : pairs) project_slow(p, worst);
    else if (!scheduled) for (std::size_t k = pairs.size(); k > 0; --k) project_slow(pairs[k - 1], worst);
    else sweep_scheduled(it % 2 == 0);
    // The deepest pair this sweep met, before the planes: a plane's depth is only what the pairs
    // pushed a body into its wall in this sweep, and the planes take it all back below.
    const double deepest_pair = worst;
    // Fixed bodies last in every sweep: they always win, and the final state honours them exactly.
    for (std::size_t i = 0; any_planes && i < bodies.size(); ++i) {
      if (bodies.plane_count[i] == 0) continue;
      const double pen = project_planes(bodies, planes, static_cast<std::uint32_t>(i));
      if (pen > 0.0) worst = std::max(worst, pen / bodies.r[i]);
    }
    result.iterations_used = it + 1;
    result.max_pen_over_radius = worst;
    if (worst <= converged) break;
    if (it + 1 >= iterations && deepest_pair <= kDeepPairOverRadius) break;
  }
  return result;
}

}  // namespace throng::detail
