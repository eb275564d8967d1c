// The pair list kept across ticks: a Verlet list (WorldSettings::pair_list_skin_m).
//
// Why: in a crowd the candidate pairs change little from one tick to the next, yet searching them
// every tick (grid sort, neighbour tests, a warm-start lookup per pair) was a large share of a
// crowd's tick. The list is searched within r_a + r_b + margin + skin. As long as no two
// bodies have together moved more than the skin since that search, every pair closer than
// r_a + r_b + margin is in it: such a pair was at most r_a + r_b + margin + (d_a + d_b) apart at the
// search. Each tick then takes from the list the pairs the margin's own test accepts (the same test
// as the grid's, on the same positions), so the solve sees exactly the pairs a search would give.
//
// Order: a Gauss-Seidel sweep converges as well as its order lets pressure travel, so the list is
// searched on the fine grid itself, two cells out (HierGrid::find_pairs), rather than on a grid
// with cells as wide as the skin: that grid's order is coarser, and the crush's p99 residual
// nearly doubled on it (docs/design/solver.md). The two-cell search
// lists the margin's pairs in exactly the order and orientation of the margin's own search
// (tested), so the tick that searches a list computes the bits a plain search computes.
//
// Pushes: each entry keeps the push its pair ended last tick with, zeroed when the warm-start
// cache could not keep it (its owner's slots were full) or when the pair was not taken (beyond the
// margin): exactly what a lookup in the cache would find. The cache itself is still written every
// tick (the state hash and checkpoints read it). So a checkpoint needs only whether a list is kept
// and where it was searched; a restored world searches there again and takes the pushes from the
// cache, and continues bit-identically.
//
// Searched ahead: a list about to be outrun is replaced by one searched where the step's final
// positions and velocities place the bodies a little ahead, so that no single tick pays for the
// whole search. Usually in three parts: begun at the end of the step that foresees the kept list
// outrun two steps on (search_ahead_begin, on a grid of its own while the kept list serves one more
// step), its scan finished at the end of the next (search_ahead_finish), set up by the step after.
// In two when the next step's check already would find it outrun (search_ahead). Once the kept list
// has ended, the next one is recorded as a restored world's list.
//
// Only where a kept list is exact and cheap: no fixed scenery (bodies against scenery get general
// pairs and planes decided per tick), shares from the two resistances alone, warm start on. A list
// whose search capped a body's candidates or relieved a pile is not kept. Anything that changes a
// pair other than motion (a body created, destroyed, teleported, grounded or lifted, a collision
// group or mask) drops the list.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "solver/contact_solver.h"
#include "solver/pair_schedule_build.h"
#include "world/world_impl.h"

namespace throng {
namespace {

// The share of the bodies whose cells search_ahead scans (HierGrid::SearchPart::kFirst).
constexpr double kAheadScanShare = 0.7;

// How far ahead search_ahead places the next list's search: each body where its last tick's
// actual velocity would carry it in this many ticks. Any reference positions keep the list exact
// (the check measures every body's displacement from where the list was searched, whatever those
// positions were); the lead only decides how long the list lasts. A body going on at its pace
// first comes closer to where the list saw it, then moves away, so the list outlasts one searched
// at the step's final positions, which had spent one move of its skin when first used. A longer
// lead left more lists outrun before the forecast saw it coming, each searched whole in a tick of
// its own (docs/design/solver.md).
constexpr double kAheadLeadTicks = 2.0;

// The share of the bodies whose cells search_ahead_begin scans, a step before the list's other
// parts: that step also predicts the positions, builds the grid and gathers its columns, and the
// step that finishes the scan only swaps them in, so it scans the larger part. The list's own
// step still sets the entries up and looks their pushes up.
constexpr double kBeginScanShare = 0.35;

// The two largest squared displacements from (x0, y0, z0)[s] to (x, y, z)[index[s]] (or [s] when
// index is null) over bodies [begin, end), folded into (first, second). Squared because the square
// root is monotonic: the two largest roots are the roots of these two, taken once at the end
// instead of twice per body. With `out`, also writes (x, y, z)[index[s]] to out[s] (the gather of
// the solver's positions, in the same pass).
struct TopTwo {
  double first = 0.0, second = 0.0;
  void add(double d) {
    // A NaN displacement (never expected: positions are finite) counts as infinite, which stays
    // the largest and fails the test in within_skin whatever comes after it.
    if (std::isnan(d)) d = std::numeric_limits<double>::infinity();
    if (!(d <= second)) {
      second = std::min(d, first);
      first = std::max(d, first);
    }
  }
};

// Also folds into `next` the displacements the next step's check would find if every body went on
// at its last tick's horizontal velocity (ax, ay over dt), and into `next2` those of the check after
// it: search_ahead_due's forecasts.
void fold_displacements(std::size_t begin, std::size_t end, const double* x, const double* y, const double* z,
                        const std::uint32_t* index, const double* x0, const double* y0, const double* z0,
                        const double* ax, const double* ay, double dt, detail::SolverBodies* out, TopTwo& top,
                        TopTwo& next, TopTwo& next2) {
  for (std::size_t s = begin; s < end; ++s) {
    const std::size_t i = index != nullptr ? index[s] : s;
    if (out != nullptr) {
      out->x[s] = x[i];
      out->y[s] = y[i];
      out->z[s] = z[i];
    }
    const double dx = x[i] - x0[s], dy = y[i] - y0[s], dz = z[i] - z0[s];
    top.add(dx * dx + dy * dy + dz * dz);
    const double mx = ax[i] * dt, my = ay[i] * dt;
    const double nx = dx + mx, ny = dy + my;
    next.add(nx * nx + ny * ny + dz * dz);
    const double fx = nx + mx, fy = ny + my;
    next2.add(fx * fx + fy * fy + dz * dz);
  }
}

// A list's columns grow to twice the entries they first need: a crowd that packs tighter has more
// pairs per body than at its first search, and a list just past the columns' capacity reallocated
// and faulted in eight columns in one tick, which made that search part several times its usual
// cost (the slowest tick of a large crowd after its first few).
template <class T>
void resize_with_room(std::vector<T>& v, std::size_t m) {
  if (m > v.capacity()) v.reserve(2 * m);
  v.resize(m);
}

// Whether no two bodies have together moved more than `skin`: the sum of the two largest
// displacements, which does not depend on the order of the bodies (a restored world checks in dense
// order, a running one in solver order) nor on how the ranges are shared among threads (each
// range's two largest, folded in range order).
bool within_skin(double first, double second, double skin) {
  // 1 um short of the skin: the argument is exact in real numbers; this keeps the rounding of the
  // displacements and of the search's reach (positions 10 km out round to ~2e-12 m) on the safe side.
  return first + second <= skin - 1e-6;
}

}  // namespace

bool World::Impl::pair_list_eligible() const {
  return settings.pair_list_skin_m > 0.0 && settings.warm_start && scenery.size() == 0 && !dyn.slow_share;
}

void World::Impl::find_pairs() {
  list.moved_next = 0.0;
  list.moved_next2 = 0.0;
  if (!pair_list_eligible()) {
    list.drop();
    build_pairs();
    return;
  }
  const std::size_t n = bodies.size();
  if (list.valid || list.restore_pending) {
    // A restored world compares with where the saved world searched its list (dense order); so
    // does a world that searched ahead at the end of its last step, which has begun that search.
    const bool restored = list.restore_pending;
    const bool ahead = list.searched_ahead;
    list.restore_pending = false;
    list.searched_ahead = false;
    const bool covers = restored ? list.restored_x.size() == n && moved_within_skin(true)
                                 : solver_order.size() == n && moved_within_skin(false);
    // The saved world's list, searched again where it was searched (its pushes come from the cache).
    if (covers && restored) {
      list.valid = search_pair_list(list.restored_x.data(), list.restored_y.data(), list.restored_z.data(), ahead);
    }
    if (covers && list.valid) {
      // A running world's check gathered the solver's positions; a restored one searched at the
      // saved positions and gathers the bodies' own.
      pairs_from_list(!restored);
      ++list.kept_ticks;
      stats.pair_list_reused = 1;
      return;
    }
    // Motion outran the skin. A list that lasted less than kMinKeptTicks did not pay for its
    // search (the crowd moves too fast for the skin): search with the margin alone for a while,
    // twice as long after each list in a row that did not pay.
    if (list.kept_ticks < PairList::kMinKeptTicks) list.back_off();
    else list.backoff = PairList::kCooldownTicks;
    list.valid = false;
    // A search begun for the step after this one is dropped with the list it was to follow (a
    // restored world drops it the same way: it checks the same displacements).
    list.ahead_begun = false;
    list.ahead_built = false;
  }
  if (list.cooldown > 0) {
    --list.cooldown;
    build_pairs();
    return;
  }
  list.kept_ticks = 0;
  list.valid = search_pair_list(bodies.x.data(), bodies.y.data(), bodies.z.data(), false);
  if (list.valid) {
    pairs_from_list(true);  // the fine grid gathered the bodies' positions
  } else {
    // A capped search or a relieved pile: this tick searches with the margin as without a list,
    // and the next ones too for a while (a capped crowd would cap the next search as well).
    list.back_off();
    search_candidates();
    setup_pairs();
  }
}

// Whether to begin the next list's search now, at the end of a step (search_ahead): the kept list
// paid, and the next step's check would find it outrun if every body went on at its last tick's
// velocity (this step's check forecast per body, moved_within_skin). Reads only what a checkpoint
// holds and this step's check, so a restored world decides the same.
// Why per body: a list searched ahead of the bodies sees their displacements shrink before they
// grow, so the check's sum does not grow at a pace that can be read from its value; each body's
// own forecast can.
bool World::Impl::search_ahead_due(int ticks) {
  if (list_record() != ListRecord::kKept || list.cooldown > 0 || list.kept_ticks < PairList::kMinKeptTicks ||
      !pair_list_eligible()) {
    return false;
  }
  return (ticks == 1 ? list.moved_next : list.moved_next2) > pair_list_skin() - 1e-6;
}

// Why: a tick that searches the list costs about twice a tick that keeps it, and one tick in four
// or five searches in a marching crowd, so those ticks were the tail. Searching ahead splits that
// work across the tick boundary: this step builds the fine grid kAheadLeadTicks ahead and scans
// the cells of the first kAheadScanShare of the bodies; the next step finishes the scan, sets the
// entries up and takes its pairs (looking their pushes up), which is why it scans less.
// The list is recorded exactly as a restored world's list to search again at those positions
// (restore_pending, restored_x), so a checkpoint or state hash taken in between holds what it holds
// for any kept list, and the next step runs the restored world's code: a world restored from that
// checkpoint searches the same list and continues with the same bits.
void World::Impl::search_ahead() {
  PairList& l = list;
  l.end_for_next();
  l.scan_complete = false;
  predict_ahead(kAheadLeadTicks, l.restored_x, l.restored_y, l.restored_z);
  // As a restored world's search builds it: at the saved positions, never relieving a pile.
  fine_grid(l.restored_x.data(), l.restored_y.data(), l.restored_z.data(), false);
  l.found.clear();
  l.ahead_capped = grid.find_pairs(solver_view(), settings.contact_margin_m + pair_list_skin(),
                                   settings.max_candidates_per_body, l.found, pool.get(),
                                   detail::HierGrid::SearchPart::kFirst, kAheadScanShare);
  l.searched_ahead = true;
}

// Where the next list is searched: each body where its last tick's horizontal velocity carries it in
// lead_ticks (dense order). Heights stay as they are (a list's pairs of grounded bodies cannot
// change height, and the forecast leaves vertical motion out too). The lead is clamped per axis to
// the skin: a body that fast moves more than half the skin a tick, so a longer lead would not make
// its lists last; the clamp also keeps a finite position finite for any finite velocity.
void World::Impl::predict_ahead(double lead_ticks, std::vector<double>& x, std::vector<double>& y,
                                std::vector<double>& z) {
  const std::size_t n = bodies.size();
  x.resize(n);
  y.resize(n);
  z.assign(bodies.z.begin(), bodies.z.end());
  const double lead = lead_ticks * settings.dt_s, skin = pair_list_skin();
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = bodies.x[i] + std::clamp(bodies.ax[i] * lead, -skin, skin);
    y[i] = bodies.y[i] + std::clamp(bodies.ay[i] * lead, -skin, skin);
  }
}

// Why a search in three parts: searched ahead in two, each part still cost about half a kept tick
// more than a kept tick, and those ticks made the tail. Begun a step earlier, the search's grid is
// built on columns of its own while the kept list serves one more step, so its work falls on three
// ticks. The next list is placed where the bodies go a step further (it is first used a step
// later), and begun when the check of the step after next would find the kept list outrun.
// Nothing of it but ahead_begun is state: the positions follow from the bodies', and the list's
// entries from the positions.
void World::Impl::search_ahead_begin() {
  list.ahead_begun = true;
  predict_begun_ahead();
  build_ahead();
}

void World::Impl::predict_begun_ahead() {
  predict_ahead(kAheadLeadTicks + 1.0, list.ahead_x, list.ahead_y, list.ahead_z);
}

// The next list's fine grid at ahead_x, ahead_y, ahead_z, the columns its search reads gathered in
// its order, and the first part of its scan into `found` (which the kept list does not use).
void World::Impl::build_ahead() {
  PairList& l = list;
  AheadGrid& g = next_grid;
  const std::size_t n = bodies.size();
  const double margin = settings.contact_margin_m;
  g.grid.build(l.ahead_x.data(), l.ahead_y.data(), bodies.r.data(), n, margin, cell0_size(margin));
  const std::vector<std::uint32_t>& order = g.grid.order();
  g.x.resize(n); g.y.resize(n); g.z.resize(n); g.r.resize(n); g.hh.resize(n);
  g.group.resize(n); g.mask.resize(n);
  for_body_ranges(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t s = begin; s < end; ++s) {
      const std::uint32_t i = order[s];
      g.x[s] = l.ahead_x[i]; g.y[s] = l.ahead_y[i]; g.z[s] = l.ahead_z[i];
      g.r[s] = bodies.r[i]; g.hh[s] = bodies.hh[i];
      g.group[s] = bodies.group[i];
      g.mask[s] = bodies.mask[i];
    }
  });
  const detail::GridBodyView view{g.x.data(), g.y.data(), g.z.data(), g.r.data(), g.hh.data(), g.group.data(),
                                  g.mask.data()};
  l.found.clear();
  l.ahead_capped = g.grid.find_pairs(view, margin + pair_list_skin(), settings.max_candidates_per_body, l.found,
                                     pool.get(), detail::HierGrid::SearchPart::kFirst, kBeginScanShare);
  l.ahead_built = true;
}

// The end of the step after search_ahead_begin: the kept list has served its last step. Its
// successor's grid and columns become the world's, the scan is finished, and the list is recorded
// as search_ahead records it, so the next step only sets its entries up and takes its pairs. A
// restored world that has not built the grid (ahead_built) builds it here: the list depends on the
// positions only.
void World::Impl::search_ahead_finish() {
  PairList& l = list;
  if (!l.ahead_built) build_ahead();
  l.end_for_next();
  l.ahead_begun = false;
  l.ahead_built = false;
  std::swap(l.restored_x, l.ahead_x);
  std::swap(l.restored_y, l.ahead_y);
  std::swap(l.restored_z, l.ahead_z);
  const std::size_t n = bodies.size();
  AheadGrid& g = next_grid;
  std::swap(grid, g.grid);
  grid_cell0 = cell0_size(settings.contact_margin_m);
  solver_order = grid.order();
  sb.resize(n);
  std::swap(sb.x, g.x); std::swap(sb.y, g.y); std::swap(sb.z, g.z);
  std::swap(sb.r, g.r); std::swap(sb.hh, g.hh);
  std::swap(sgroup, g.group);
  std::swap(smask, g.mask);
  for_body_ranges(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t s = begin; s < end; ++s) {
      const std::uint32_t i = solver_order[s];
      sb.grounded[s] = bodies.grounded[i];
      sb.id[s] = bodies.id[i].value;
    }
  });
  l.ahead_capped += grid.find_pairs(solver_view(), settings.contact_margin_m + pair_list_skin(),
                                    settings.max_candidates_per_body, l.found, pool.get(),
                                    detail::HierGrid::SearchPart::kRest);
  l.scan_complete = true;
  l.searched_ahead = true;
}

// Whether the bodies moved within the skin since the list's search: from the saved positions of a
// restored world (dense order), or from the kept list's (solver order, gathering the solver's
// positions on the way).
bool World::Impl::moved_within_skin(bool restored) {
  const std::size_t n = bodies.size();
  const double* x = bodies.x.data();
  const double* y = bodies.y.data();
  const double* z = bodies.z.data();
  const std::uint32_t* index = restored ? nullptr : solver_order.data();
  const double* x0 = restored ? list.restored_x.data() : list.x.data();
  const double* y0 = restored ? list.restored_y.data() : list.y.data();
  const double* z0 = restored ? list.restored_z.data() : list.z.data();
  detail::SolverBodies* out = restored ? nullptr : &sb;
  const std::size_t tasks = (n + kBodiesPerTask - 1) / kBodiesPerTask;
  list.range_top.resize(6 * tasks);
  const double* ax = bodies.ax.data();
  const double* ay = bodies.ay.data();
  const double dt = settings.dt_s;
  for_body_ranges(n, [&](std::size_t begin, std::size_t end) {
    TopTwo top, next, next2;
    fold_displacements(begin, end, x, y, z, index, x0, y0, z0, ax, ay, dt, out, top, next, next2);
    double* range = &list.range_top[6 * (begin / kBodiesPerTask)];
    range[0] = top.first;
    range[1] = top.second;
    range[2] = next.first;
    range[3] = next.second;
    range[4] = next2.first;
    range[5] = next2.second;
  });
  TopTwo all, all_next, all_next2;
  for (std::size_t t = 0; t < tasks; ++t) {
    const double* range = &list.range_top[6 * t];
    all.add(range[0]);
    all.add(range[1]);
    all_next.add(range[2]);
    all_next.add(range[3]);
    all_next2.add(range[4]);
    all_next2.add(range[5]);
  }
  list.moved_next = std::sqrt(all_next.first) + std::sqrt(all_next.second);
  list.moved_next2 = std::sqrt(all_next2.first) + std::sqrt(all_next2.second);
  return within_skin(std::sqrt(all.first), std::sqrt(all.second), pair_list_skin());
}

// The skin the fine grid can search (HierGrid::max_extra_margin): the configured one unless the
// bodies are so small that their cells are narrower than it. Depends on the radii only.
double World::Impl::pair_list_skin() {
  const double margin = settings.contact_margin_m;
  return std::min(settings.pair_list_skin_m, detail::HierGrid::max_extra_margin(cell0_size(margin), margin));
}

// Searches the list at positions (x, y, z) (dense order): the bodies' own, or a restored world's
// saved ones. Returns false (and leaves the fine grid and the solver's bodies set up at the bodies'
// positions) if the list cannot be kept.
bool World::Impl::search_pair_list(const double* x, const double* y, const double* z, bool ahead) {
  const double margin = settings.contact_margin_m;
  PairList& l = list;
  std::uint32_t capped = 0;
  if (ahead) {
    // search_ahead or search_ahead_finish built the fine grid at these positions and scanned its
    // first part (search_ahead_finish all of it).
    capped = l.ahead_capped;
    if (!l.scan_complete) {
      capped += grid.find_pairs(solver_view(), margin + pair_list_skin(), settings.max_candidates_per_body, l.found,
                                pool.get(), detail::HierGrid::SearchPart::kRest);
    }
    l.scan_complete = false;
  } else {
    // The fine grid gives the bodies' order. Pile relief moves the bodies (only ever at their own
    // positions: a kept list's search relieved none, and a search at the same positions again would
    // not either).
    const bool relieved = fine_grid(x, y, z, x == bodies.x.data());
    if (relieved) return false;
    // The fine grid's own search, two cells out: the pairs come in the order a search with the
    // margin lists them, so this tick's pairs (the entries within the margin) are that search's.
    l.found.clear();
    capped =
        grid.find_pairs(solver_view(), margin + pair_list_skin(), settings.max_candidates_per_body, l.found, pool.get());
  }
  if (capped != 0) {
    if (x != bodies.x.data()) fine_grid(bodies.x.data(), bodies.y.data(), bodies.z.data(), false);
    return false;
  }
  // Per entry what stays while the list is kept: the separation target, the margin's reach (the
  // grid's candidate test, hier_grid.cpp scan_one: a grounded pair's height gap cannot change), the
  // schedule slot and the share. The pushes are looked up in the cache by this tick's
  // pairs_from_list (and kept only for the entries within the margin).
  const std::size_t m = l.found.size();
  resize_with_room(l.a, m);
  resize_with_room(l.b, m);
  resize_with_room(l.target, m);
  resize_with_room(l.reach, m);
  resize_with_room(l.share, m);
  resize_with_room(l.lambda, m);
  resize_with_room(l.slot, m);
  gather_list_resistances();
  for_entry_ranges(m, [&](std::size_t begin, std::size_t end) { set_up_entries(begin, end, margin); });
  l.shares_stale = false;
  l.all_fast = std::all_of(l.target.begin(), l.target.end(), [](double t) { return t >= 0.0; });
  l.fresh = true;
  l.x = sb.x;
  l.y = sb.y;
  l.z = sb.z;
  return true;
}

// Entries [begin, end) of a list just searched: what stays while the list is kept (the separation
// target, the margin's reach, the schedule slot and the share), computed as pair_target,
// slot_fields and set_list_share do. One pass over raw columns: as calls per entry (each reloading
// the vectors it reads) this pass was a fifth of a search.
void World::Impl::set_up_entries(std::size_t begin, std::size_t end, double margin) {
  PairList& l = list;
  const detail::CandidatePair* found = l.found.data();
  const double* r = sb.r.data();
  const double* z = sb.z.data();
  const double* hh = sb.hh.data();
  const std::uint8_t* grounded = sb.grounded.data();
  const double* resistance = l.resistance.data();
  std::uint32_t* ea = l.a.data();
  std::uint32_t* eb = l.b.data();
  double* target_of = l.target.data();
  double* reach_of = l.reach.data();
  double* share_of = l.share.data();
  PairList::Slot* slot = l.slot.data();
  for (std::size_t e = begin; e < end; ++e) {
    const std::uint32_t a = found[e].a, b = found[e].b;
    ea[e] = a;
    eb[e] = b;
    const double rsum = r[a] + r[b];
    const double gap_z = std::fabs(z[b] - z[a]) - hh[a] - hh[b];
    const bool both_grounded = (grounded[a] & grounded[b]) != 0;
    const double target = detail::separation_target(both_grounded, rsum, gap_z);
    target_of[e] = target;
    const double reach = rsum + margin;
    reach_of[e] = both_grounded && gap_z >= reach ? 0.0 : reach;
    const double r_min = std::min(r[a], r[b]);
    const double share = params::share_a_fast(resistance[a], resistance[b]);
    share_of[e] = share;
    slot[e] = {a, b, static_cast<float>(target), static_cast<float>(share), static_cast<float>(1.0 / r_min),
               detail::fast_warm_cap(r_min)};
  }
}

// The bodies' resistances in solver order, for the entries' shares: one sequential read per entry's
// body instead of a gather through solver_order (the entries' bodies are scattered within a band).
void World::Impl::gather_list_resistances() {
  const std::size_t n = solver_order.size();
  list.resistance.resize(n);
  for_body_ranges(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t s = begin; s < end; ++s) list.resistance[s] = bodies.resistance[solver_order[s]];
  });
}

// Entry e's share from the resistances (the list is kept only where nothing else enters one) and
// its warm-start cap.
void World::Impl::set_list_share(std::size_t e) {
  PairList& l = list;
  const std::uint32_t a = l.a[e], b = l.b[e];
  l.share[e] = params::share_a_fast(l.resistance[a], l.resistance[b]);
  l.slot[e].share = static_cast<float>(l.share[e]);
  l.slot[e].warm_cap = detail::fast_warm_cap(std::min(sb.r[a], sb.r[b]));
}

// The entries' shares again after a resistance changed.
void World::Impl::refresh_list_shares() {
  gather_list_resistances();
  for_entry_ranges(list.a.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e) set_list_share(e);
  });
  list.shares_stale = false;
}

World::Impl::ListRecord World::Impl::list_record() const {
  const std::size_t n = bodies.size();
  if (list.valid && solver_order.size() == n && list.x.size() == n) return ListRecord::kKept;
  if (list.restore_pending && list.restored_x.size() == n) return ListRecord::kPending;
  return ListRecord::kNone;
}

// This tick's pairs: the list's entries the margin's test accepts at the bodies' positions now,
// with the push each kept (or, right after a search, the push the cache holds). They stay in the
// list (of_pair names them) unless solve() needs them as SolverPairs (materialize_list_pairs).
template <bool kFresh>
void World::Impl::take_list_pairs() {
  PairList& l = list;
  const std::size_t m = l.a.size();
  const double* x = sb.x.data();
  const double* y = sb.y.data();
  std::uint32_t* of_pair = l.of_pair.data();
  // Fixed ranges of entries, each compacted on its own and then moved to where the earlier ranges'
  // taken entries end: the same list for any number of threads.
  const auto tasks = static_cast<std::uint32_t>((m + kEntriesPerTask - 1) / kEntriesPerTask);
  l.range_taken.resize(tasks + 1);
  l.range_warm.resize(tasks);
  auto take_range = [&](std::uint32_t t) {
    const std::size_t e0 = t * kEntriesPerTask, e1 = std::min(m, e0 + kEntriesPerTask);
    std::size_t k = e0;  // compacted within the range's own slots first
    std::size_t warm = 0;
    for (std::size_t e = e0; e < e1; ++e) {
      const std::uint32_t a = l.a[e], b = l.b[e];
      // The grid's candidate test (hier_grid.cpp, scan_one) with the margin; a pair with an
      // airborne body also tests its height gap now.
      const double dx = x[b] - x[a];
      const double dy = y[b] - y[a];
      const double reach = l.reach[e];
      bool live = !(dx * dx + dy * dy >= reach * reach);
      if (l.target[e] < 0.0) live &= !(std::fabs(sb.z[b] - sb.z[a]) - sb.hh[a] - sb.hh[b] >= reach);
      // Not a pair this tick: no push (a search with the margin would not look one up). Masked,
      // not selected: the compiler made the select a branch, mispredicted as often as the test
      // above is random. Right after a search every entry starts at 0 here and the taken ones look
      // their push up in the cache below (looking up every entry, to keep this loop free of
      // branches, cost a third more lookups).
      float lambda = kFresh ? 0.0f : l.lambda[e];
      std::uint32_t bits;
      std::memcpy(&bits, &lambda, 4);
      bits &= 0u - static_cast<std::uint32_t>(live);
      std::memcpy(&lambda, &bits, 4);
      l.lambda[e] = lambda;
      warm += lambda > 0.0f ? 1 : 0;
      // Written whether taken or not (the next write goes to the same slot unless it was): no
      // branch on a test that fails for a third of the entries in no order. The slot is the
      // range's own (k <= e < e1).
      of_pair[k] = static_cast<std::uint32_t>(e);
      k += live ? 1 : 0;
    }
    if constexpr (kFresh) {
      // warm_push's lookup, inline (a call per entry cost more than the lookups); a list is kept
      // only with warm start on (pair_list_eligible), so warm_push's check is not needed here.
      const std::uint32_t* id = sb.id.data();
      const std::uint32_t* order = solver_order.data();
      const detail::WarmEntry* warm_slots = bodies.warm.data();
      const std::uint8_t* warm_count = bodies.warm_count.data();
      for (std::size_t q = e0; q < k; ++q) {
        const std::uint32_t e = of_pair[q];
        const float lambda = detail::kept_pair_push(id, order, warm_slots, warm_count, l.a[e], l.b[e]);
        l.lambda[e] = lambda;
        warm += lambda > 0.0f ? 1 : 0;
      }
    }
    l.range_taken[t] = static_cast<std::uint32_t>(k - e0);
    l.range_warm[t] = static_cast<std::uint32_t>(warm);
  };
  run_tasks(pool.get(), tasks, take_range);
  // Close the gaps, in range order (a range's taken entries move down, never past a later range's).
  std::size_t k = 0, warm = 0;
  for (std::uint32_t t = 0; t < tasks; ++t) {
    const std::size_t e0 = t * kEntriesPerTask;
    if (k != e0) std::memmove(of_pair + k, of_pair + e0, l.range_taken[t] * sizeof(std::uint32_t));
    k += l.range_taken[t];
    warm += l.range_warm[t];
  }
  l.live = k;
  warm_pairs = warm;
  stats.candidate_pairs = static_cast<std::uint32_t>(k);
}

void World::Impl::pairs_from_list(bool gathered) {
  const std::size_t n = bodies.size();
  if (!gathered) {
    for (std::size_t s = 0; s < n; ++s) {
      const std::uint32_t i = solver_order[s];
      sb.x[s] = bodies.x[i];
      sb.y[s] = bodies.y[i];
      sb.z[s] = bodies.z[i];
    }
  }
  PairList& l = list;
  const std::size_t m = l.a.size();
  if (l.shares_stale) refresh_list_shares();
  resize_with_room(l.of_pair, m);
  if (l.fresh) take_list_pairs<true>();
  else take_list_pairs<false>();
  l.fresh = false;
  pairs_in_list = true;
  pairs.clear();
  stats.capped_bodies = 0;
}

// This tick's pairs from the list as SolverPairs (an unscheduled solve, or pairs with an airborne
// body, which the general code projects).
void World::Impl::materialize_list_pairs() {
  const PairList& l = list;
  pairs.resize(l.live);
  for (std::size_t k = 0; k < l.live; ++k) {
    const std::uint32_t e = l.of_pair[k];
    detail::SolverPair& p = pairs[k];
    p.a = l.a[e];
    p.b = l.b[e];
    p.share_a = l.share[e];
    p.target = l.target[e];
    p.lambda = static_cast<double>(l.lambda[e]);
    p.depth_start = 0.0;
    p.resolved_once = 0;
  }
  pairs_in_list = false;
}

// The pairs a kept list takes this tick, scheduled straight from the list (pair_schedule_build.h):
// the same schedule as from the same pairs as SolverPairs. Only a list of fast pairs is scheduled
// here (solve() materializes any other), and the list is kept only without scenery, so no body
// touches a plane: every pair is fast.
void World::Impl::schedule_list_pairs(double conflict) {
  const PairList& l = list;
  struct Source {
    const PairList::Slot* slots;
    const std::uint32_t* of_pair;
    const float* lambda;
    std::size_t live;
    std::size_t size() const { return live; }
    std::uint32_t a(std::size_t k) const { return slots[of_pair[k]].a; }
    std::uint32_t b(std::size_t k) const { return slots[of_pair[k]].b; }
    bool fast(const detail::SolverBodies&, std::size_t) const { return true; }
    // slot_fields of the entry (resolved_once is false at the start of a solve), precomputed.
    detail::SlotFields slot(std::size_t k, const detail::SolverBodies&, float, float) const {
      const std::uint32_t e = of_pair[k];
      const PairList::Slot& q = slots[e];
      return {q.a, q.b, q.target, q.share, q.share, detail::capped_warm_push(lambda[e], q.warm_cap), q.inv_r_min};
    }
  };
  detail::build_pair_schedule_from(sb, Source{l.slot.data(), l.of_pair.data(), l.lambda.data(), l.live}, conflict,
                                   pair_schedule, pool.get());
}

}  // namespace throng
