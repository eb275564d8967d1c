#pragma once
// The order in which one Gauss-Seidel sweep visits the pairs, rebuilt every tick.
//
// Why: the broadphase lists a body's pairs one after another, so in that order every projection
// reads the position the previous one just wrote (store -> load -> sqrt -> division -> store):
// the sweep ran one dependent chain of ~50 cycles per pair and the core sat idle.
//
// Each pair gets a level: one more than the latest level of any earlier pair sharing one of its
// bodies. Pairs of one level share no body, so they can run in any order, side by side (out of
// order, or in SIMD lanes). Visiting the levels in order keeps every body's pairs in their original
// relative order, and two projections that share no body touch disjoint memory, so a sweep in level
// order computes bit-for-bit what a sweep in broadphase order with the same arithmetic computes,
// and the reverse level order the reverse sweep. Nothing about convergence changes; only the
// waiting goes. (The crowd solve that uses this order also does its arithmetic on float
// displacements, see SolverBodies::u, and its fast pairs keep their start-of-tick normals and a
// larger warm-start cap, see fast_pair_kernel.h: it is not the double pair-order solve's method.)
//
// The pairs are cut into chunks of kScheduleChunkPairs consecutive pairs (a band of grid rows)
// and every level lies within one chunk: still a valid reordering, and a sweep then works
// through one band of the crowd at a time. Levels over the whole list are diagonal wavefronts
// across the entire crowd, which at 100,000 bodies touched a new cache line for nearly every
// body of every pair and made the level order no faster than the broadphase order.
//
// Fast pairs (both bodies grounded, neither touching fixed scenery: the crowd's common case) are
// copied into structure-of-arrays form for the kernel in fast_pair_kernel.h; the others stay in
// SolverPair form and are projected by the general code.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "solver/solver_data.h"
#include "throng/core/worker_pool.h"

namespace throng::detail {

// A few grid rows: levels stay wide enough for four SIMD lanes and the out-of-order core, and the
// chunk's bodies stay in L2 while it is swept. A chunk is also the band a sweep may leave out as
// calm (kCalmPushOverRadius), and smaller bands cut the calm rim more finely; 2,048 was the
// fastest of the sizes measured (docs/design/solver.md, "The pair schedule and the caps").
inline constexpr std::size_t kScheduleChunkPairs = 2048;

// Bands are swept in blocks of this many consecutive bands, and blocks that share no body run side
// by side (PairSchedule::phase_block). Within a block a sweep still carries pressure from band to
// band in one pass; between blocks it takes a phase. Four keeps a 100,000-body crush's ~60 bands in
// ~15 blocks (enough to share among four threads) while a 5,000-body crowd is one block and sweeps
// exactly as one list of bands (docs/design/solver.md, "Threads").
inline constexpr std::size_t kBlockBands = 4;

// Warm-start pushes above this fraction of the smaller radius are cut back (see apply_warm_start
// in contact_solver.cpp): the general pairs' cap, whose projection re-takes the pair's direction
// after every push.
inline constexpr double kWarmStartCapOverRadius = 0.5;
// The fast pairs' cap (fast_pair_kernel.h): their warm start is a sum along fixed normals and can
// carry a packed crowd's pressure, which grows towards its middle (several radii per pair in the
// core). Cut at 0.5 r the core had to be rebuilt every tick; 8 r carries the crush's core, and
// larger caps only made `mixed` worse (docs/design/solver.md, "Warm start"). Every fast pair
// carries it, whatever its share: pressure in a crowd of unequal weights crosses the pairs of a
// heavy and a light body too (docs/design/solver.md, "Carried pressure").
inline constexpr double kFastWarmStartCapOverRadius = 8.0;

// The warm start is a guess: last tick's pushes along this tick's normals. Where the pushes on a
// body balance (a packed crowd's pressure) they move it little, however large each is; where
// they do not (a pair capped lower than its neighbours, bodies sliding round a small fixed body
// so that the normals turn, a pair that ended) the guess alone can carry a body a metre, past
// bodies the pair search saw apart and the solve therefore does not have: the deepest overlaps of
// a tick were such unseen pairs, made in that tick (traced on crush with a post at its goal). So
// a body's net warm-start move is cut to this fraction of its radius, comparable with the search's
// contact margin; the pairs keep their pushes (lambda), so the sweeps can still give them back.
// Smaller, a jam that steps its full speed rebuilds its pressure too slowly; larger, unseen pairs
// get through (the worst-tick figures per cap are in docs/design/solver.md).
inline constexpr double kWarmStartMoveCapOverRadius = 0.1;

// The solve adds sweeps (WorldSettings::extra_iterations) while the deepest pair its last sweep
// met was deeper than this fraction of the pair's smaller radius: well under the quarter radius a
// tick may leave at worst, so the sweeps it adds bring such ticks inside it (0.08 did as well at
// more sweeps; the figures are in docs/design/solver.md, "Extra sweeps while a pair is deep").
inline constexpr double kDeepPairOverRadius = 0.1;

// A pair held together by its neighbours (a jam), not by its own bodies' steps, starts its tick
// at the conflict share (WorldSettings::conflict_share_limit), as if already pushed once. Why: the
// exact share is what a pair sees on first contact. A pair of a light and a heavy body inside a
// packed crowd of unequal weights carries a push of a radius or more from tick to tick; started at
// the exact share, its warm start and first push threw that whole push on the light body, and the
// sweeps had to rebuild the heavy body's part every tick, which 8 sweeps never did (the mixed
// crowd's worst ticks, docs/design/solver.md, "Held pairs"). The test: the push carried from last
// tick exceeds the pair's penetration at the start of this one (what its own bodies' steps closed)
// by more than this fraction of the smaller radius. A light body walking into a heavy one carries
// about what it closes each tick and keeps the exact ratio (tested); the margin keeps float
// rounding and a slowing walker from tipping such a pair over.
inline constexpr double kHeldPushMarginOverRadius = 0.02;
// In double for the general pairs, in float on the fast pairs' columns (mark_held_fast_pairs).
template <typename T>
inline bool held_by_neighbours(T carried_push, T start_pen, T inv_r_min) {
  return (carried_push - std::max(start_pen, T{0})) * inv_r_min > static_cast<T>(kHeldPushMarginOverRadius);
}

// A fast pair's warm-start cap in metres, from its smaller radius. Both schedule sources
// (pair_schedule_build.h, the kept list's records in world_pair_list.cpp) call this, so a pair gets
// the same cap bits either way (tested).
inline double fast_warm_cap(double r_min) { return kFastWarmStartCapOverRadius * r_min; }

// A scheduled sweep leaves out a band once no band sharing a body with it changed a push (pushed
// or gave back) by this fraction of the smaller radius or more in its last sweep (after the first
// kFullSweeps sweeps, which visit every band; in a solve with scenery planes every sweep visits
// every band, as a plane's push is no band's). When every band is calm the solve stops. Why: in a
// crush the pressure sits in the core; the crowd's rim settles after a sweep or two and its later
// sweeps change next to nothing. Leaving a band out is exact only when it would have changed
// nothing (tested with the threshold at the smallest float); at 1e-3 the crush scene's residual
// is no worse and about a third of its band sweeps are left out (docs/design/solver.md). `mixed`
// leaves none out: its charging cavalry keeps every band busy. Bands left out are counted in
// StepStats.
inline constexpr float kCalmPushOverRadius = 1e-3f;
inline constexpr std::uint32_t kFullSweeps = 2;

struct PairSchedule {
  struct Level {
    std::uint32_t fast_begin, fast_end;  // range in the fast arrays
    std::uint32_t slow_begin, slow_end;  // range in `slow`
  };
  std::vector<Level> levels;

  // The bands (kScheduleChunkPairs consecutive pairs each): band c holds levels
  // [band_level[c], band_level[c + 1]). Every band that shares a body with band c lies in
  // [band_wake_lo[c], band_wake_hi[c]] (a superset: from the bands whose body index ranges overlap
  // band c's). In a crowd of one size that is c - 1 .. c + 1; the pairs of larger bodies come
  // after the finest level's pairs and touch bodies all over the crowd, so their bands (and the
  // bands they overlap) have wide ranges.
  std::vector<std::uint32_t> band_level;
  std::vector<std::uint32_t> band_wake_lo, band_wake_hi;

  // The sweep's order of the bands, the same for any number of threads. Block k holds bands
  // [block_band[k], block_band[k + 1]) (kBlockBands of them). Blocks are coloured greedily in
  // order so that blocks of one colour share no body (their bands' body ranges do not overlap);
  // phase p holds the blocks phase_block[phase_begin[p], phase_begin[p + 1]), the blocks of colour
  // p in increasing order. A forward sweep runs the phases in order, each block's bands in order;
  // a reverse sweep the phases in reverse, each block's bands in reverse. The blocks of one phase
  // touch disjoint bodies (and their own padding bodies, SolverBodies::pad_body), so they can run
  // in any order or at once and compute the same bits. A crowd of one size has two colours,
  // alternate blocks; the blocks of larger bodies' pairs overlap many and get colours of their own.
  std::vector<std::uint32_t> block_band;
  std::vector<std::uint32_t> phase_begin, phase_block;
  std::size_t block_count() const { return block_band.empty() ? 0 : block_band.size() - 1; }
  std::size_t phase_count() const { return phase_begin.empty() ? 0 : phase_begin.size() - 1; }
  // Block k's fast pairs: one range, as the bands' levels follow each other.
  std::uint32_t block_fast_begin(std::size_t k) const { return levels[band_level[block_band[k]]].fast_begin; }
  std::uint32_t block_fast_end(std::size_t k) const { return levels[band_level[block_band[k + 1]] - 1].fast_end; }
  // kCalmPushOverRadius, or 0 to visit every band in every sweep (tests compare the two).
  float calm_push_over_radius = kCalmPushOverRadius;
  // Scratch for solve_contacts: each band's largest change of push over the smaller radius in its
  // last sweep, whether the current sweep visits it, and a prefix count of the busy bands.
  std::vector<float> band_activity;
  std::vector<std::uint8_t> band_swept;
  std::vector<std::uint32_t> band_busy_before;

  // Fast pairs in level order, in single precision (see SolverBodies::u). Each keeps its normal
  // from the start of the solve (unit, from a to b; the id-derived one for coincident cores) and
  // its penetration along it then (target - distance), so that its penetration at any point of
  // the solve is pen0 - n . (u_b - u_a) (fast_pair_kernel.h).
  std::vector<std::uint32_t> a, b;
  std::vector<float> nx, ny, pen0;
  std::vector<float> target;  // read only for push events' start depth
  // Share of the next push: exact until the pair's first push, then the conflict share (from the
  // start for a pair held by its neighbours, held_by_neighbours). This is also the fast pairs' only
  // record of SolverPair::resolved_once, which nothing reads after the solve, so it is not copied
  // back.
  std::vector<float> share_now;
  std::vector<float> share_exact;      // the pair's own share (for push events)
  // The conflict share is std::clamp(exact share, lo, hi); clamping is idempotent, so clamping
  // share_now again after later pushes changes nothing. [0, 1] when the limit is off.
  float conflict_lo = 0.0f, conflict_hi = 1.0f;
  // Accumulated push; on entry last tick's, already cut to the warm-start cap.
  std::vector<float> lambda;
  std::vector<float> inv_r_min;        // 1 / smaller radius
  std::vector<std::uint32_t> src;      // index in the caller's pair list, kNoPair for padding
  static constexpr std::uint32_t kNoPair = UINT32_MAX;

  std::vector<std::uint32_t> slow;     // other pairs in level order: indices in the caller's list

  // Scratch.
  // Per thread and body: the first level the body's next pair in the band may take (low 32 bits,
  // counted from the band's first level), valid only under the band's stamp (high 32 bits), so
  // that no array is cleared per band or per build (stamp_base moves on by the band count).
  std::vector<std::vector<std::uint64_t>> level_stamp;
  std::uint32_t stamp_base = 0;
  std::vector<std::uint32_t> pair_level;  // per pair, from its band's first level, kSlow bit set if slow
  // Per band: its level count, fast pair count, and each of its levels' fast / slow pair counts
  // (band c's at c * kScheduleChunkPairs: a band has at most that many levels).
  std::vector<std::uint32_t> band_levels, band_fast_pairs;
  std::vector<std::uint32_t> band_level_fast, band_level_slow;
  std::vector<std::uint32_t> fast_count, slow_count;
  std::vector<std::uint32_t> band_body_lo, band_body_hi;  // solver index range of each band's bodies
  std::vector<std::uint32_t> block_body_lo, block_body_hi, block_colour;
  std::vector<std::uint8_t> colour_taken;
  std::vector<double> block_worst;  // solve_contacts: each block's deepest pair of the sweep
  std::vector<std::uint32_t> block_events;  // store_fast_pushes: each block's first event

  std::size_t fast_size() const { return a.size(); }  // including the padding (lambda 0)
  std::size_t band_count() const { return band_level.empty() ? 0 : band_level.size() - 1; }

  // Sets band_swept for the next sweep: a band is visited if a band in its wake range changed a
  // push by `calm` or more in its last sweep (band_activity). A band left out does not move in that
  // sweep, so its activity becomes 0. Returns the number of bands left out.
  std::uint32_t choose_bands(float calm);
};

// Runs fn(k) for every block k of `s`, phase by phase (in order, or in reverse when !forward), the
// blocks of a phase on the pool's threads (in increasing order without a pool). Blocks of one phase
// share no body, so what fn does to its block's bodies and pairs comes out the same bits however
// the blocks are shared out; the phases are barriers.
template <class Fn>
void for_each_block(const PairSchedule& s, WorkerPool* pool, bool forward, Fn&& fn) {
  const std::size_t phases = s.phase_count();
  for (std::size_t q = 0; q < phases; ++q) {
    const std::size_t p = forward ? q : phases - 1 - q;
    const std::uint32_t first = s.phase_begin[p];
    const std::uint32_t blocks = s.phase_begin[p + 1] - first;
    auto task = [&](std::uint32_t t) { fn(s.phase_block[first + t]); };
    run_tasks(pool, blocks, task);
  }
}

// Both bodies grounded, neither touching fixed scenery: the kernel's pairs (fast_pair_kernel.h).
inline bool is_fast_pair(const SolverBodies& bodies, const SolverPair& p) {
  return p.target >= 0.0 && (bodies.plane_count[p.a] | bodies.plane_count[p.b]) == 0;
}

// Builds the schedule of `pairs` (fast copies take the pairs' current lambda, cut to the warm-start
// cap, and share). Bodies' u must be zero (the start of the solve).
void build_pair_schedule(const SolverBodies& bodies, const std::vector<SolverPair>& pairs, double conflict_limit,
                         PairSchedule& s, WorkerPool* pool = nullptr);

// Copies the fast pairs' lambda back into the caller's list. A scheduled solve leaves them in the
// schedule (the world reads them from there, in schedule order); tests compare against the list.
void write_back_pair_schedule(const PairSchedule& s, std::vector<SolverPair>& pairs);

}  // namespace throng::detail
