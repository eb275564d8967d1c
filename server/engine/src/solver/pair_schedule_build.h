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

template <class Source>
void build_pair_schedule_from(const SolverBodies& bodies, const Source& pairs, double conflict_limit, PairSchedule& s) {
  const std::size_t np = pairs.size();
  // resize + fill, not assign: assign beyond the capacity reallocates to the exact size, so a list
  // that keeps growing by a few entries would allocate in every tick that sets a new high.
  s.next_level.resize(bodies.size());
  std::fill(s.next_level.begin(), s.next_level.end(), 0u);
  s.pair_level.resize(np);
  s.fast_count.clear();
  s.slow_count.clear();
  std::uint32_t fast_total = 0;
  // Level of each pair, with the fast/slow split in the top bit; counts per level.
  constexpr std::uint32_t kSlow = 0x80000000u;
  std::uint32_t chunk_base = 0;  // first level of the current chunk
  // Bands: the solver index range of the bodies each band touches, kept in registers.
  s.band_level.clear();
  s.band_body_lo.clear();
  s.band_body_hi.clear();
  std::uint32_t body_lo = UINT32_MAX, body_hi = 0;
  for (std::size_t k = 0; k < np; ++k) {
    const std::uint32_t pa = pairs.a(k), pb = pairs.b(k);
    if (k % kScheduleChunkPairs == 0) {
      if (k > 0) {
        s.band_body_lo.push_back(body_lo);
        s.band_body_hi.push_back(body_hi);
        body_lo = UINT32_MAX;
        body_hi = 0;
      }
      chunk_base = static_cast<std::uint32_t>(s.fast_count.size());
      s.band_level.push_back(chunk_base);
    }
    body_lo = std::min({body_lo, pa, pb});
    body_hi = std::max({body_hi, pa, pb});
    const std::uint32_t lv = std::max({s.next_level[pa], s.next_level[pb], chunk_base});
    s.next_level[pa] = s.next_level[pb] = lv + 1;
    if (lv == s.fast_count.size()) {
      s.fast_count.push_back(0);
      s.slow_count.push_back(0);
    }
    const bool fast = pairs.fast(bodies, k);
    if (fast) {
      ++s.fast_count[lv];
      ++fast_total;
    } else {
      ++s.slow_count[lv];
    }
    s.pair_level[k] = lv | (fast ? 0u : kSlow);
  }
  // Counting sort by level (stable: within a level, pairs keep the broadphase order).
  const std::size_t level_count = s.fast_count.size();
  s.band_level.push_back(static_cast<std::uint32_t>(level_count));
  if (np > 0) {
    s.band_body_lo.push_back(body_lo);
    s.band_body_hi.push_back(body_hi);
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
  for (std::size_t k = 0; k < np; ++k) {
    const std::uint32_t lv = s.pair_level[k];
    if (lv & kSlow) s.slow[s.slow_count[lv & ~kSlow]++] = static_cast<std::uint32_t>(k);
    else s.src[s.fast_count[lv]++] = static_cast<std::uint32_t>(k);
  }
  s.a.resize(slots); s.b.resize(slots); s.nx.resize(slots); s.ny.resize(slots); s.pen0.resize(slots);
  s.target.resize(slots); s.share_now.resize(slots); s.share_exact.resize(slots);
  s.lambda.resize(slots);
  s.inv_r_min.resize(slots);
  const std::uint32_t pad_body = static_cast<std::uint32_t>(bodies.size());  // SolverBodies' spare slot
  const double* x = bodies.x.data();
  const double* y = bodies.y.data();
  // Shares are in [0, 1], so [0, 1] leaves them exact when the limit is off.
  s.conflict_lo = conflict_limit > 0.0 ? static_cast<float>(conflict_limit) : 0.0f;
  s.conflict_hi = conflict_limit > 0.0 ? static_cast<float>(1.0 - conflict_limit) : 1.0f;
  for (std::uint32_t f = 0; f < slots; ++f) {
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
}


}  // namespace throng::detail
