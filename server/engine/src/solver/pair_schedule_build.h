#pragma once
// build_pair_schedule over any list of pairs: the world's SolverPair list, or the pairs a kept pair
// list takes this tick (world_pair_list.cpp), which are read from the list itself instead of being
// copied into SolverPairs first (the copy and the schedule's gather of it were a tenth of a kept
// tick). A Source provides size(), a(k), b(k), fast(bodies, k) (is_fast_pair) and
// slot(k, bodies, lo, hi) (what a fast pair's slot holds, from slot_fields or precomputed with the
// same arithmetic); the schedule is the same whatever holds the pairs.
#include <algorithm>
#include <cmath>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "solver/pair_projection.h"
#include "solver/pair_schedule.h"

namespace throng::detail {

// What the schedule stores of a fast pair, in the kernel's single precision.
struct SlotFields {
  std::uint32_t a, b;
  float target, share_now, share_exact, lambda, inv_r_min;
};

// The warm-start push a fast pair starts its solve with: cut to the cap (fast_warm_cap).
inline float capped_warm_push(double lambda, double cap) { return static_cast<float>(std::min(lambda, cap)); }

// A fast pair's slot from its double fields: the same share the general projection would pick
// (contact_solver.cpp), the capped warm push and the reciprocal of the smaller radius.
inline SlotFields slot_fields(std::uint32_t a, std::uint32_t b, double target, double share_a, double lambda,
                              bool resolved_once, double r_min, float conflict_lo, float conflict_hi) {
  const float share = static_cast<float>(share_a);
  return {a,
          b,
          static_cast<float>(target),
          resolved_once ? std::clamp(share, conflict_lo, conflict_hi) : share,
          share,
          capped_warm_push(lambda, fast_warm_cap(r_min)),
          static_cast<float>(1.0 / r_min)};
}

// Fast pairs [f0, f1) whose carried push exceeds their start penetration by more than the margin
// (held_by_neighbours, in float on the schedule's columns) take the conflict share from the start
// (clamping changes nothing when the limit is off: [0, 1]). Whether a pair is held is
// data-dependent (about half of a packed crowd's pairs): as a branch its mispredictions cost a
// kept crush tick several percent, so it is a select, four pairs at a time.
inline void mark_held_fast_pairs(PairSchedule& s, std::uint32_t f0, std::uint32_t f1) {
  const float lo = s.conflict_lo, hi = s.conflict_hi;
  const float* const lambda = s.lambda.data();
  const float* const pen0 = s.pen0.data();
  const float* const inv_r_min = s.inv_r_min.data();
  float* const share = s.share_now.data();
  std::uint32_t f = f0;
#if defined(__SSE2__)
  // The same test as held_by_neighbours: max(pen0, 0) may differ from std::max only in the sign of a
  // zero, which changes no difference lambda - max; the clamp is the kernel's (fast_pair_kernel.h).
  const __m128 zero = _mm_setzero_ps(), margin = _mm_set1_ps(static_cast<float>(kHeldPushMarginOverRadius));
  const __m128 lo4 = _mm_set1_ps(lo), hi4 = _mm_set1_ps(hi);
  for (; f + 4 <= f1; f += 4) {
    const __m128 excess = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(lambda + f), _mm_max_ps(_mm_loadu_ps(pen0 + f), zero)),
                                     _mm_loadu_ps(inv_r_min + f));
    const __m128 held = _mm_cmpgt_ps(excess, margin);
    const __m128 now = _mm_loadu_ps(share + f);
    const __m128 clamped = _mm_max_ps(_mm_min_ps(now, hi4), lo4);
    _mm_storeu_ps(share + f, _mm_or_ps(_mm_and_ps(held, clamped), _mm_andnot_ps(held, now)));
  }
#endif
  for (; f < f1; ++f) {
    if (held_by_neighbours(lambda[f], pen0[f], inv_r_min[f])) share[f] = std::clamp(share[f], lo, hi);
  }
}

// The world's own pair list.
struct SolverPairSource {
  const std::vector<SolverPair>& pairs;
  std::size_t size() const { return pairs.size(); }
  std::uint32_t a(std::size_t k) const { return pairs[k].a; }
  std::uint32_t b(std::size_t k) const { return pairs[k].b; }
  bool fast(const SolverBodies& bodies, std::size_t k) const { return is_fast_pair(bodies, pairs[k]); }
  SlotFields slot(std::size_t k, const SolverBodies& bodies, float conflict_lo, float conflict_hi) const {
    const SolverPair& p = pairs[k];
    return slot_fields(p.a, p.b, p.target, p.share_a, p.lambda, p.resolved_once != 0,
                       std::min(bodies.r[p.a], bodies.r[p.b]), conflict_lo, conflict_hi);
  }
};

// Blocks of kBlockBands bands, coloured so that blocks of one colour share no body, and the
// phases (see PairSchedule::block_band). Blocks x blocks interval tests, like the bands' wake.
inline void colour_blocks(PairSchedule& s) {
  const std::size_t band_count = s.band_count();
  const std::size_t block_count = (band_count + kBlockBands - 1) / kBlockBands;
  s.block_band.resize(block_count + 1);
  s.block_body_lo.resize(block_count);
  s.block_body_hi.resize(block_count);
  s.block_colour.resize(block_count);
  s.block_worst.resize(block_count);
  std::uint32_t colours = 0;
  for (std::size_t k = 0; k < block_count; ++k) {
    const std::size_t c0 = k * kBlockBands, c1 = std::min(band_count, c0 + kBlockBands);
    s.block_band[k] = static_cast<std::uint32_t>(c0);
    std::uint32_t lo = UINT32_MAX, hi = 0;
    for (std::size_t c = c0; c < c1; ++c) {
      lo = std::min(lo, s.band_body_lo[c]);
      hi = std::max(hi, s.band_body_hi[c]);
    }
    s.block_body_lo[k] = lo;
    s.block_body_hi[k] = hi;
    // The smallest colour no earlier block sharing a body range with this one has.
    s.colour_taken.resize(colours + 1);
    std::fill(s.colour_taken.begin(), s.colour_taken.end(), std::uint8_t{0});
    for (std::size_t j = 0; j < k; ++j) {
      if (s.block_body_lo[j] <= hi && lo <= s.block_body_hi[j]) s.colour_taken[s.block_colour[j]] = 1;
    }
    std::uint32_t colour = 0;
    while (s.colour_taken[colour] != 0) ++colour;
    s.block_colour[k] = colour;
    colours = std::max(colours, colour + 1);
  }
  s.block_band[block_count] = static_cast<std::uint32_t>(band_count);
  // Counting sort of the blocks by colour (stable: increasing block order within a phase).
  s.phase_begin.resize(colours + 1);
  std::fill(s.phase_begin.begin(), s.phase_begin.end(), 0u);
  for (std::size_t k = 0; k < block_count; ++k) ++s.phase_begin[s.block_colour[k] + 1];
  for (std::uint32_t p = 0; p < colours; ++p) s.phase_begin[p + 1] += s.phase_begin[p];
  s.phase_block.resize(block_count);
  for (std::size_t k = 0; k < block_count; ++k) {
    // phase_begin[colour] is the next free slot of the colour while filling; restored below.
    s.phase_block[s.phase_begin[s.block_colour[k]]++] = static_cast<std::uint32_t>(k);
  }
  for (std::uint32_t p = colours; p > 0; --p) s.phase_begin[p] = s.phase_begin[p - 1];
  if (!s.phase_begin.empty()) s.phase_begin[0] = 0;
}

template <class Source>
void build_pair_schedule_from(const SolverBodies& bodies, const Source& pairs, double conflict_limit, PairSchedule& s,
                              WorkerPool* pool = nullptr) {
  const std::size_t np = pairs.size();
  constexpr std::size_t kChunk = kScheduleChunkPairs;
  const std::size_t nb = (np + kChunk - 1) / kChunk;
  // Level of each pair: one more than the latest level of an earlier pair of the same band sharing
  // a body, and at least the band's first level. An earlier band's levels all lie below this
  // band's first, so a band's levels depend on its own pairs only: the bands are levelled side by
  // side, each from its own first level 0, then put one after the other.
  // resize, not assign: assign beyond the capacity reallocates to the exact size, so a list that
  // keeps growing by a few entries would allocate in every tick that sets a new high.
  const unsigned threads = pool != nullptr ? pool->threads() : 1u;
  if (s.level_stamp.size() < threads) s.level_stamp.resize(threads);
  if (std::uint64_t{s.stamp_base} + nb + 1 > UINT32_MAX) {
    for (std::vector<std::uint64_t>& st : s.level_stamp) std::fill(st.begin(), st.end(), std::uint64_t{0});
    s.stamp_base = 0;
  }
  for (unsigned t = 0; t < threads; ++t) {
    // New entries are 0: stamp 0 is no band's.
    if (s.level_stamp[t].size() < bodies.size()) s.level_stamp[t].resize(bodies.size(), 0);
  }
  const std::uint64_t stamp0 = std::uint64_t{s.stamp_base} + 1;
  s.stamp_base += static_cast<std::uint32_t>(nb);
  s.pair_level.resize(np);
  s.band_levels.resize(nb);
  s.band_fast_pairs.resize(nb);
  s.band_body_lo.resize(nb);
  s.band_body_hi.resize(nb);
  s.band_level_fast.resize(nb * kChunk);
  s.band_level_slow.resize(nb * kChunk);
  // The fast/slow split in the top bit of pair_level.
  constexpr std::uint32_t kSlow = 0x80000000u;
  auto level_band = [&](std::uint32_t c, unsigned thread) {
    std::uint64_t* const next = s.level_stamp[thread].data();
    const std::uint64_t stamp = (stamp0 + c) << 32;
    std::uint32_t* const fast_n = s.band_level_fast.data() + c * kChunk;
    std::uint32_t* const slow_n = s.band_level_slow.data() + c * kChunk;
    std::uint32_t levels = 0, fast_pairs = 0;
    std::uint32_t body_lo = UINT32_MAX, body_hi = 0;  // the solver index range the band touches
    const std::size_t k1 = std::min(np, (c + 1) * kChunk);
    for (std::size_t k = c * kChunk; k < k1; ++k) {
      const std::uint32_t pa = pairs.a(k), pb = pairs.b(k);
      body_lo = std::min({body_lo, pa, pb});
      body_hi = std::max({body_hi, pa, pb});
      const std::uint64_t na = next[pa], nb_ = next[pb];
      const std::uint32_t la = (na & ~std::uint64_t{UINT32_MAX}) == stamp ? static_cast<std::uint32_t>(na) : 0u;
      const std::uint32_t lb = (nb_ & ~std::uint64_t{UINT32_MAX}) == stamp ? static_cast<std::uint32_t>(nb_) : 0u;
      const std::uint32_t lv = std::max(la, lb);
      next[pa] = next[pb] = stamp | (lv + 1);
      if (lv == levels) {
        fast_n[lv] = slow_n[lv] = 0;
        ++levels;
      }
      const bool fast = pairs.fast(bodies, k);
      if (fast) {
        ++fast_n[lv];
        ++fast_pairs;
      } else {
        ++slow_n[lv];
      }
      s.pair_level[k] = lv | (fast ? 0u : kSlow);
    }
    s.band_levels[c] = levels;
    s.band_fast_pairs[c] = fast_pairs;
    s.band_body_lo[c] = body_lo;
    s.band_body_hi[c] = body_hi;
  };
  run_tasks(pool, static_cast<std::uint32_t>(nb), level_band);
  // The bands' levels one after the other; counts per level.
  s.band_level.resize(nb + 1);
  std::uint32_t level_count = 0, fast_total = 0;
  for (std::size_t c = 0; c < nb; ++c) {
    s.band_level[c] = level_count;
    level_count += s.band_levels[c];
    fast_total += s.band_fast_pairs[c];
  }
  s.band_level[nb] = level_count;
  s.fast_count.resize(level_count);
  s.slow_count.resize(level_count);
  for (std::size_t c = 0; c < nb; ++c) {
    std::copy_n(s.band_level_fast.data() + c * kChunk, s.band_levels[c], s.fast_count.data() + s.band_level[c]);
    std::copy_n(s.band_level_slow.data() + c * kChunk, s.band_levels[c], s.slow_count.data() + s.band_level[c]);
  }
  // Which bands share a body with which, as an interval of band indices per band (a superset:
  // bands whose body ranges overlap). Bands of one crowd level touch c - 1 .. c + 1; the bands of
  // pairs with a larger body (listed after the finest level's pairs) span wide ranges. Bands x
  // bands interval tests: a crowd has tens of bands, so this is a few microseconds.
  const std::size_t band_count = s.band_count();
  s.band_wake_lo.resize(band_count);
  s.band_wake_hi.resize(band_count);
  for (std::size_t c = 0; c < band_count; ++c) {
    std::uint32_t lo = static_cast<std::uint32_t>(c), hi = static_cast<std::uint32_t>(c);
    for (std::size_t d = 0; d < band_count; ++d) {
      if (s.band_body_lo[d] <= s.band_body_hi[c] && s.band_body_lo[c] <= s.band_body_hi[d]) {
        lo = std::min(lo, static_cast<std::uint32_t>(d));
        hi = std::max(hi, static_cast<std::uint32_t>(d));
      }
    }
    s.band_wake_lo[c] = lo;
    s.band_wake_hi[c] = hi;
  }
  colour_blocks(s);
  s.levels.resize(level_count);
  // Each level's fast range is padded to a multiple of four with pairs that never touch anything
  // (on SolverBodies' spare slot, see below), so the four-lane kernel takes every pair (levels hold ~20-35 pairs, and the
  // up to three left over went the scalar way, at three times the cost).
  std::uint32_t fast_at = 0, slow_at = 0;
  for (std::size_t lv = 0; lv < level_count; ++lv) {
    const std::uint32_t padded = (s.fast_count[lv] + 3u) & ~3u;
    s.levels[lv] = {fast_at, fast_at + padded, slow_at, slow_at + s.slow_count[lv]};
    s.fast_count[lv] = fast_at;  // now the next free slot of the level
    s.slow_count[lv] = slow_at;
    fast_at = s.levels[lv].fast_end;
    slow_at = s.levels[lv].slow_end;
  }
  // Scatter only the pair index, then fill the fast arrays front to back: one random write per
  // pair instead of one into each of nine arrays. Padding slots keep kNoPair.
  const std::uint32_t slots = fast_at;
  s.src.resize(slots);
  std::fill(s.src.begin(), s.src.end(), PairSchedule::kNoPair);
  s.slow.resize(np - fast_total);
  // Counting sort by level (stable: within a level, pairs keep the broadphase order). A band's
  // pairs go to its own levels only: the bands side by side.
  auto scatter_band = [&](std::uint32_t c) {
    const std::uint32_t first = s.band_level[c];
    const std::size_t k1 = std::min(np, (c + 1) * kChunk);
    for (std::size_t k = c * kChunk; k < k1; ++k) {
      const std::uint32_t lv = s.pair_level[k];
      if (lv & kSlow) s.slow[s.slow_count[first + (lv & ~kSlow)]++] = static_cast<std::uint32_t>(k);
      else s.src[s.fast_count[first + lv]++] = static_cast<std::uint32_t>(k);
    }
  };
  run_tasks(pool, static_cast<std::uint32_t>(nb), scatter_band);
  s.a.resize(slots); s.b.resize(slots); s.nx.resize(slots); s.ny.resize(slots); s.pen0.resize(slots);
  s.target.resize(slots); s.share_now.resize(slots); s.share_exact.resize(slots);
  s.lambda.resize(slots);
  s.inv_r_min.resize(slots);
  const double* x = bodies.x.data();
  const double* y = bodies.y.data();
  // Shares are in [0, 1], so [0, 1] leaves them exact when the limit is off.
  s.conflict_lo = conflict_limit > 0.0 ? static_cast<float>(conflict_limit) : 0.0f;
  s.conflict_hi = conflict_limit > 0.0 ? static_cast<float>(1.0 - conflict_limit) : 1.0f;
  // Each slot on its own (a random read of its bodies' positions: the build's slowest loop), so
  // the bands are shared out among the pool's threads. Every band holds at least one level (its
  // first pair opens one); band c's padding moves its own spare body (SolverBodies::pad_body).
  auto fill_band = [&](std::uint32_t band) {
    const std::uint32_t pad_body = bodies.pad_body(band);
    const std::uint32_t f0 = s.levels[s.band_level[band]].fast_begin;
    const std::uint32_t f1 = s.levels[s.band_level[band + 1] - 1].fast_end;
    for (std::uint32_t f = f0; f < f1; ++f) {
      if (s.src[f] == PairSchedule::kNoPair) {
        // Separated (1 m apart, target 0) with no push: every lane test skips it, it moves its body
        // (the spare slot, no real pair's) by exactly zero, and its direction is finite.
        s.a[f] = s.b[f] = pad_body;
        s.nx[f] = 1.0f;
        s.ny[f] = 0.0f;
        s.pen0[f] = -1.0f;
        s.target[f] = 0.0f;
        s.share_now[f] = s.share_exact[f] = 0.0f;
        s.lambda[f] = 0.0f;
        s.inv_r_min[f] = 0.0f;
        continue;
      }
      const SlotFields p = pairs.slot(s.src[f], bodies, s.conflict_lo, s.conflict_hi);
      s.a[f] = p.a;
      s.b[f] = p.b;
      // The pair's normal for this tick (fast_pair_kernel.h), from the double positions (exact
      // whatever the distance from the origin), and its penetration along it.
      double dx = x[p.b] - x[p.a], dy = y[p.b] - y[p.a];
      const double dist = std::sqrt(dx * dx + dy * dy);
      if (dist > 1e-9 * p.target) {
        dx /= dist;
        dy /= dist;
      } else {
        coincident_direction(bodies.id[p.a], bodies.id[p.b], dx, dy);
      }
      s.nx[f] = static_cast<float>(dx);
      s.ny[f] = static_cast<float>(dy);
      s.pen0[f] = static_cast<float>(static_cast<double>(p.target) - dist);
      s.target[f] = p.target;
      s.share_now[f] = p.share_now;
      s.share_exact[f] = p.share_exact;
      s.lambda[f] = p.lambda;
      s.inv_r_min[f] = p.inv_r_min;
    }
  };
  const auto bands = static_cast<std::uint32_t>(s.band_count());
  run_tasks(pool, bands, fill_band);
  // Pairs held by their neighbours start at the conflict share (held_by_neighbours): a pass of its
  // own over the contiguous columns. Inside fill_band the same test slowed a kept crush tick by a
  // tenth (the compiler stopped inlining the fill); here it vectorises. Padding slots have no push
  // and never qualify.
  mark_held_fast_pairs(s, 0, static_cast<std::uint32_t>(slots));
}


}  // namespace throng::detail
