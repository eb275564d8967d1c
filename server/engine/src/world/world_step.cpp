// The tick: a short list of named phases, each timed.
//   dynamic parameters -> push coefficients -> move -> broadphase -> scenery planes -> solve ->
//   warm-start cache and push events -> actual velocities.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "solver/contact_solver.h"
#include "world/body_passes.h"
#include "world/warm_store.h"
#include "world/world_impl.h"

namespace throng {
namespace {

using Clock = std::chrono::steady_clock;
double micros_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
}

}  // namespace

const StepStats& World::step() {
  Impl& w = *impl_;
  const auto t0 = Clock::now();
  w.stats = StepStats{};
  w.stats.tick = w.tick + 1;
  if (w.params_scratch.size() < w.bodies.size()) w.size_reorder_scratch();
  if (w.scenery_dirty || (w.scenery.size() > 0 && w.max_body_reach_m + 1.0 > w.scenery_reach_m)) {
    w.rebuild_scenery_cells(w.max_body_reach_m + 1.0);
  }

  auto t = Clock::now();
  w.update_dynamic_params();
  w.refresh_coefficients();
  w.stats.params_us = micros_since(t);

  t = Clock::now();
  w.move_bodies();
  w.stats.move_us = micros_since(t);

  t = Clock::now();
  w.find_pairs();
  w.stats.broadphase_us = micros_since(t);

  t = Clock::now();
  w.build_scenery_planes();
  w.solve(true);
  if (w.moved_past_margin()) {
    // The search saw every pair within the margin of where the bodies stood; a body the sweeps
    // carried further (a light body squeezed out between two heavy ones) may now overlap a body the
    // solve never had. Search again where the bodies are and go on solving: each pair starts with
    // the push it already made this tick (stored first, then looked up as a warm push, but not
    // applied again), so the sweeps can give it back, and the normals are re-taken where the bodies
    // now stand. A kept pair list's indices are the first search's: dropped.
    w.store_warm_start_and_events();
    w.list.drop();
    w.second_solve = true;
    // The tick's search figures stay the first search's (as its solver figures do), except that a
    // capped second search is still reported.
    const StepStats first = w.stats;
    w.fine_grid(w.bodies.x.data(), w.bodies.y.data(), w.bodies.z.data(), false);
    w.search_candidates();
    w.setup_pairs();
    w.build_scenery_planes();
    w.solve(false);
    w.stats.candidate_pairs = first.candidate_pairs;
    w.stats.scenery_planes = first.scenery_planes;
    w.stats.capped_bodies = std::max(first.capped_bodies, w.stats.capped_bodies);
    w.stats.second_search = 1;
  }
  w.store_warm_start_and_events();
  w.second_solve = false;
  w.stats.solve_us = micros_since(t);

  w.finish_tick();
  w.last_reorder.clear();
  // The next list's search: finished if the last step began it, else begun in two parts if the
  // next step's check would find the kept list outrun (search_ahead), else in three if the check
  // after it would (search_ahead_begin).
  const bool finish = w.list.ahead_begun;
  const bool ahead = !finish && w.search_ahead_due(1);
  const bool begin = !finish && !ahead && w.search_ahead_due(2);
  const bool searching = finish || ahead || begin;
  if (w.reorder_due(searching)) {
    w.reorder_dense();
  } else if (w.surely_no_search_work(searching)) {
    w.settle_params();  // a no-op unless a re-sort left the records in their old order
  }
  if (searching) {
    t = Clock::now();
    if (finish) w.search_ahead_finish();
    else if (ahead) w.search_ahead();
    else w.search_ahead_begin();
    w.stats.broadphase_us += micros_since(t);
    w.stats.pair_list_searched_ahead = finish ? 0 : 1;
    w.stats.pair_list_ahead_finished = finish ? 1 : 0;
  }
  w.stats.total_us = micros_since(t0);
  return w.stats;
}

void World::Impl::move_bodies() {
  const std::size_t n = bodies.size();
  // The start and moved copies are written in the same pass as the move (five separate copies
  // were five more passes over memory at 100,000 bodies).
  start_x.resize(n); start_y.resize(n); start_z.resize(n);
  moved_x.resize(n); moved_y.resize(n);
  const double dt = settings.dt_s;
  const double carry = settings.blocked_motion_carry;
  if (scenery.size() == 0) {
    // Nothing can stop a move: the vectorised kernel (body_passes.cpp).
    const detail::MoveColumns columns{bodies.x.data(),       bodies.y.data(),      bodies.z.data(),  bodies.vx.data(),
                                      bodies.vy.data(),      bodies.vz.data(),     bodies.push_x.data(),
                                      bodies.push_y.data(),  bodies.grounded.data(), start_x.data(),
                                      start_y.data(),        start_z.data(),       moved_x.data(),   moved_y.data()};
    for_body_ranges(n, [&](std::size_t begin, std::size_t end) {
      detail::move_free_bodies(columns.from(begin), end - begin, dt, carry);
    });
    return;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double x0 = bodies.x[i], y0 = bodies.y[i], z0 = bodies.z[i];
    start_x[i] = x0; start_y[i] = y0; start_z[i] = z0;
    double dx = bodies.vx[i] * dt, dy = bodies.vy[i] * dt;
    if (carry > 0.0) {
      const double keep = detail::carried_step_share(dx, dy, bodies.push_x[i], bodies.push_y[i], carry);
      dx *= keep;
      dy *= keep;
    }
    const double dz = bodies.grounded[i] ? 0.0 : bodies.vz[i] * dt;
    double frac = 1.0;
    // A move longer than half a radius could step over a thin wall in one tick (a charging horse):
    // sweep it against the scenery and stop at the first contact.
    const double half_r = 0.5 * bodies.r[i];
    if (dx * dx + dy * dy + dz * dz > half_r * half_r) {
      const geom::Capsule cap{{x0, y0, z0 - bodies.hh[i]}, {x0, y0, z0 + bodies.hh[i]}, bodies.r[i]};
      frac = scenery.first_hit_fraction(cap, {dx, dy, dz});
      if (frac < 1.0) ++stats.tunnel_clamps;
    }
    const double x1 = x0 + dx * frac, y1 = y0 + dy * frac;
    bodies.x[i] = x1; bodies.y[i] = y1;
    bodies.z[i] = z0 + dz * frac;
    moved_x[i] = x1; moved_y[i] = y1;
  }
}

double World::Impl::cell0_size(double search_margin) {
  if (settings.cell_size_m > 0.0) return settings.cell_size_m;
  // Finest cell = diameter of the median body plus margin: most bodies land on level 0 and test
  // only their 3x3 neighbourhood; bigger bodies go to coarser levels.
  if (cell0_dirty) {
    median_scratch.assign(bodies.r.begin(), bodies.r.end());
    if (median_scratch.empty()) return 1.0;
    auto mid = median_scratch.begin() + static_cast<std::ptrdiff_t>(median_scratch.size() / 2);
    std::nth_element(median_scratch.begin(), mid, median_scratch.end());
    median_radius_m = *mid;
    cell0_dirty = false;
  }
  return 2.0 * (median_radius_m + search_margin);
}

void World::Impl::build_pairs() {
  fine_grid(bodies.x.data(), bodies.y.data(), bodies.z.data(), true);
  search_candidates();
  setup_pairs();
}

// The broadphase grid with the contact margin at positions (x, y, z) (dense order): the solver
// order, and the solver's bodies gathered in it. Returns whether a pile was relieved (then the
// grid and the bodies are at the relieved positions, which are the bodies' own).
bool World::Impl::fine_grid(const double* x, const double* y, const double* z, bool allow_relief) {
  const std::size_t n = bodies.size();
  const double margin = settings.contact_margin_m;
  grid_cell0 = cell0_size(margin);
  grid.build(x, y, bodies.r.data(), n, margin, grid_cell0);
  const bool relieved = allow_relief && relieve_piles();
  if (relieved) {
    x = bodies.x.data();
    y = bodies.y.data();
    z = bodies.z.data();
    grid.build(x, y, bodies.r.data(), n, margin, grid_cell0);
  }
  solver_order = grid.order();
  const std::vector<std::uint32_t>& order = solver_order;
  sb.resize(n);
  sgroup.resize(n);
  smask.resize(n);
  for_body_ranges(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t s = begin; s < end; ++s) {
      const std::uint32_t i = order[s];
      sb.x[s] = x[i]; sb.y[s] = y[i]; sb.z[s] = z[i];
      sb.r[s] = bodies.r[i]; sb.hh[s] = bodies.hh[i];
      sb.grounded[s] = bodies.grounded[i];
      sb.id[s] = bodies.id[i].value;
      sgroup[s] = bodies.group[i];
      smask[s] = bodies.mask[i];
    }
  });
  return relieved;
}

void World::Impl::search_candidates() {
  candidates.clear();
  stats.capped_bodies =
      grid.find_pairs(solver_view(), settings.contact_margin_m, settings.max_candidates_per_body, candidates, pool.get());
  stats.candidate_pairs = static_cast<std::uint32_t>(candidates.size());
}

double World::Impl::pair_target(std::uint32_t a, std::uint32_t b) const {
  return detail::separation_target((sb.grounded[a] & sb.grounded[b]) != 0, sb.r[a] + sb.r[b],
                                   std::fabs(sb.z[b] - sb.z[a]) - sb.hh[a] - sb.hh[b]);
}

float World::Impl::warm_push(std::uint32_t a, std::uint32_t b) const {
  if (!settings.warm_start) return 0.0f;
  return detail::kept_pair_push(sb.id.data(), solver_order.data(), bodies.warm.data(), bodies.warm_count.data(), a, b);
}

void World::Impl::setup_pairs() {
  const std::vector<std::uint32_t>& order = solver_order;
  pairs_in_list = false;
  // A quarter more room at each new high: with a kept pair list this vector is filled only by the
  // ticks that search twice, so it meets a compressing crowd's new highs one at a time.
  if (pairs.capacity() < candidates.size()) pairs.reserve(candidates.size() + candidates.size() / 4);
  pairs.resize(candidates.size());
  warm_pairs = 0;
  if (dyn.slow_share) {
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      const std::uint32_t a = candidates[k].a, b = candidates[k].b;
      // Pair-dependent terms (facing) need the direction between the bodies.
      double nx = sb.x[b] - sb.x[a], ny = sb.y[b] - sb.y[a];
      const double d = std::sqrt(nx * nx + ny * ny);
      if (d > 0.0) { nx /= d; ny /= d; }
      const float lambda = warm_push(a, b);
      pairs[k] = {a, b, pair_target(a, b), pair_share(order[a], order[b], nx, ny), static_cast<double>(lambda), 0.0, 0};
      warm_pairs += lambda > 0.0f ? 1 : 0;
    }
    return;
  }
  // Shares from the two resistances: one pass over raw columns (as calls per pair, each reloading
  // the vectors it reads, this pass was most of setting up a battle's pairs).
  const detail::CandidatePair* cand = candidates.data();
  detail::SolverPair* out = pairs.data();
  const std::uint32_t* ord = order.data();
  const double* resistance = bodies.resistance.data();
  const double* r = sb.r.data();
  const double* z = sb.z.data();
  const double* hh = sb.hh.data();
  const std::uint8_t* grounded = sb.grounded.data();
  const std::uint32_t* id = sb.id.data();
  const detail::WarmEntry* warm = bodies.warm.data();
  const std::uint8_t* warm_count = bodies.warm_count.data();
  const bool warm_start = settings.warm_start;
  std::uint32_t warm_found = 0;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const std::uint32_t a = cand[k].a, b = cand[k].b;
    const double target = detail::separation_target((grounded[a] & grounded[b]) != 0, r[a] + r[b],
                                                    std::fabs(z[b] - z[a]) - hh[a] - hh[b]);
    const float lambda = warm_start ? detail::kept_pair_push(id, ord, warm, warm_count, a, b) : 0.0f;
    out[k] = {a, b, target, params::share_a_fast(resistance[ord[a]], resistance[ord[b]]), static_cast<double>(lambda),
              0.0, 0};
    warm_found += lambda > 0.0f ? 1 : 0;
  }
  warm_pairs = warm_found;
}

bool World::Impl::moved_past_margin() const {
  const double limit2 = settings.contact_margin_m * settings.contact_margin_m;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const double dx = bodies.x[i] - moved_x[i], dy = bodies.y[i] - moved_y[i];
    if (dx * dx + dy * dy > limit2) return true;
  }
  return false;
}

void World::Impl::solve(bool apply_warm_start) {
  const std::size_t n = sb.size();
  const double conflict_limit = policy.mode() == params::PushMode::ratio ? settings.conflict_share_limit : 0.0;
  // The second solve of a tick goes on the way the first went (its pairs all start with the first
  // solve's pushes, which would otherwise send every such tick to the scheduled solve).
  const bool scheduled = second_solve ? first_solve_scheduled
                                      : detail::wants_schedule(pairs_in_list ? list.live : pairs.size(), warm_pairs);
  first_solve_scheduled = scheduled;
  // A kept list's pairs are scheduled straight from the list; the general code needs SolverPairs.
  if (pairs_in_list && !(scheduled && list.all_fast)) materialize_list_pairs();
  sb.displaced = scheduled;
  if (scheduled) {
    std::fill(sb.u.begin(), sb.u.end(), 0.0f);
    if (pairs_in_list) schedule_list_pairs(conflict_limit);
    else detail::build_pair_schedule(sb, pairs, conflict_limit, pair_schedule, pool.get());
  }
  if (records_push_events()) detail::measure_start_depths(sb, pairs, planes, scheduled ? &pair_schedule : nullptr);
  // A list of fast pairs only is scheduled straight from the list (`pairs` is stale then), and the
  // schedule marks its fast pairs itself. In the second solve of a tick the carried push is the
  // first solve's (already applied, the start penetration about zero): a pair that pushed then has
  // had its first push of the tick, so its later pushes and give-backs take the conflict share,
  // as they would have in one longer solve.
  if (!(scheduled && pairs_in_list)) detail::mark_held_pairs(sb, pairs, scheduled ? &pair_schedule : nullptr, conflict_limit);
  if (settings.warm_start && apply_warm_start) {
    if (scheduled) detail::apply_warm_start(sb, pairs, planes, pair_schedule, conflict_limit, pool.get());
    else detail::apply_warm_start(sb, pairs, planes, conflict_limit);
  }
  const detail::SolveResult r = detail::solve_contacts(sb, pairs, planes, settings.iterations, settings.extra_iterations,
                                                       settings.converged_pen_over_radius, conflict_limit,
                                                       pair_schedule, scheduled, pool.get());
  // The tick's solver figures are its first solve's (a second one is counted in second_search).
  if (!second_solve) {
    stats.iterations_used = r.iterations_used;
    stats.band_sweeps = r.band_sweeps;
    stats.band_sweeps_skipped = r.band_sweeps_skipped;
    stats.max_pen_over_radius = r.max_pen_over_radius;
  }
  const std::vector<std::uint32_t>& order = solver_order;
  for_body_ranges(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t s = begin; s < end; ++s) {
      const std::uint32_t i = order[s];
      bodies.x[i] = sb.px(static_cast<std::uint32_t>(s));
      bodies.y[i] = sb.py(static_cast<std::uint32_t>(s));
      bodies.z[i] = sb.z[s];
    }
  });
  verify_scenery_after_solve();
}

void World::Impl::store_warm_start_and_events() {
  std::fill(bodies.warm_count.begin(), bodies.warm_count.end(), 0);
  const std::vector<std::uint32_t>& order = solver_order;
  // The push events describe the tick's first solve (its start depths, shares and pushes); the
  // second solve's pushes, which include the first's, are what the next tick starts from.
  const bool record = records_push_events() && !second_solve;
  // Room for an event per pair and plane: the buffer only grows (warm-up); event_count says how
  // many this tick holds.
  const std::size_t most = (sb.displaced ? pair_schedule.fast_size() + pair_schedule.slow.size() : pairs.size()) +
                           planes.size();
  if (record && events.size() < most) events.resize(most);
  if (record) event_count = 0;
  // A kept pair list keeps each pair's push as the cache does (zero where the cache cannot).
  float* list_lambda = list.valid ? list.lambda.data() : nullptr;
  const std::uint32_t* list_entry = list.of_pair.data();
  auto keep_pair = [&](std::uint32_t k) {
    const detail::SolverPair& p = pairs[k];
    const float kept = detail::keep_warm_push(order.data(), bodies.warm.data(), bodies.warm_count.data(), p.a, p.b,
                                              sb.id[p.a], sb.id[p.b], static_cast<float>(p.lambda));
    if (list_lambda != nullptr) list_lambda[list_entry[k]] = kept;
    if (record && p.lambda > 0.0) {
      events[event_count++] = {ObjectId{sb.id[p.a]}, ObjectId{sb.id[p.b]}, static_cast<float>(p.depth_start),
                               static_cast<float>(p.share_a), static_cast<float>(p.lambda)};
    }
  };
  if (sb.displaced) {
    // A scheduled solve left the fast pairs' pushes in the schedule: read them there, in schedule
    // order (sequential; copying them back into the pair list first was a random write per pair).
    const std::size_t fast_events =
        detail::store_fast_pushes(pair_schedule, sb,
                                  {order.data(), bodies.warm.data(), bodies.warm_count.data(), list_lambda, list_entry,
                                   record ? events.data() : nullptr},
                                  pool.get());
    if (record) event_count = fast_events;
    for (const std::uint32_t k : pair_schedule.slow) keep_pair(k);
  } else {
    for (std::uint32_t k = 0; k < pairs.size(); ++k) keep_pair(k);
  }
  if (record) {
    for (const detail::SolverPlane& pl : planes) {
      if (pl.depth_start <= 0.0) continue;
      events[event_count++] = {ObjectId{sb.id[pl.body]}, pl.fixed, static_cast<float>(pl.depth_start),
                               static_cast<float>(pl.share), static_cast<float>(pl.depth_start * pl.share)};
    }
  }
}

// The re-sort's ticks: the first of each kReorderPeriodTicks if it surely does no search work, else
// the second if that one surely does none; when neither, that period has none (a re-sort costs about
// as much as half a search, and the two together made the heaviest ticks). "Surely none": the tick
// keeps a list it already kept the tick before and does not begin the next one. A list's first
// kept tick is not told apart from the tick that finished a search ahead (both count one kept
// tick, and a checkpoint holds no more), so it counts as a search's tick. Reads only the tick, the
// list's state and this step's decision to search ahead, so a restored world re-sorts on the same
// ticks.
bool World::Impl::reorder_due(bool searching_ahead) const {
  const std::uint64_t phase = tick % kReorderPeriodTicks;
  if (phase > 1) return false;
  if (list_record() != ListRecord::kKept) return phase == 0;  // no list (search_ahead_due needs one)
  if (!surely_no_search_work(searching_ahead)) return false;
  // Phase 1 re-sorts only if phase 0 could not: then it was this list's first kept tick.
  return phase == 0 || list.kept_ticks == 2;
}

// This tick kept a list it already kept the tick before and begins no search; without a kept list
// (crowds too sparse or too fast for one) every tick is alike, so any tick will do.
bool World::Impl::surely_no_search_work(bool searching_ahead) const {
  if (list_record() != ListRecord::kKept) return true;
  // kept_ticks counts this tick: 0 searched the list in this tick, 1 is its first kept tick.
  return !searching_ahead && list.kept_ticks >= 2;
}

// Every few ticks the dense arrays are put into the broadphase's spatial order, so that the
// gather/scatter between dense and solver order walks memory almost sequentially instead of
// jumping at random (bodies spawned in random order would otherwise stay scattered forever).
//
// The parameter records follow later (params_order, settle_params): they are cold (read when
// parameters change, or every tick only by policies that use dynamic parameters, which settle them
// first), yet at well over a hundred bytes a body their copy was the larger part of a re-sort, and
// re-sort ticks were the heaviest kind of tick.
void World::Impl::reorder_dense() {
  std::vector<std::uint32_t>& order = solver_order;
  if (order.size() != bodies.size()) return;  // bodies were created or destroyed since the solve
  settle_params();  // the records follow one permutation at a time
  bodies.permute(order, body_scratch);
  params_order.assign(order.begin(), order.end());
  for (std::size_t s = 0; s < order.size(); ++s) slots[bodies.id[s].index()].ref = static_cast<std::uint32_t>(s);
  // Published before the order becomes the identity (assign within the capacity: no allocation
  // after the first re-sort).
  last_reorder.assign(order.begin(), order.end());
  // Dense index s now holds solver slot s; a kept pair list (in solver indices) stays valid.
  for (std::size_t s = 0; s < order.size(); ++s) order[s] = static_cast<std::uint32_t>(s);
}

// The re-sort's buffers (a copy of every dense column and of the parameter records: megabytes for a
// large crowd) are allocated and faulted in on the first step after the crowd grew, not on the tick
// of the first re-sort or settling: a world's first steps (a spawn's overlaps, a first search) are
// its heaviest anyway, while a re-sort tick otherwise costs little more than a kept one.
void World::Impl::size_reorder_scratch() {
  const std::size_t n = bodies.size();
  body_scratch.for_each_column([&](auto& column) { column.resize(n); });
  body_scratch.warm.resize(n * detail::kWarmSlots);
  params_scratch.resize(n);
  params_order.reserve(n);
  last_reorder.reserve(n);
}

void World::Impl::settle_params() {
  if (params_order.empty()) return;
  params_scratch.resize(params_order.size());
  for (std::size_t s = 0; s < params_order.size(); ++s) params_scratch[s] = body_params[params_order[s]];
  params_scratch.swap(body_params);
  params_order.clear();
}

void World::Impl::finish_tick() {
  const detail::FinishColumns columns{bodies.x.data(),      bodies.y.data(),      bodies.z.data(),  moved_x.data(),
                                      moved_y.data(),       start_x.data(),       start_y.data(),   start_z.data(),
                                      bodies.push_x.data(), bodies.push_y.data(), bodies.ax.data(), bodies.ay.data(),
                                      bodies.az.data()};
  const double inv_dt = 1.0 / settings.dt_s;
  for_body_ranges(bodies.size(), [&](std::size_t begin, std::size_t end) {
    detail::finish_bodies(columns.from(begin), end - begin, inv_dt);
  });
  ++tick;
}

}  // namespace throng
