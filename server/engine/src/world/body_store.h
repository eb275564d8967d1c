#pragma once
// Dense structure-of-arrays storage of the movable bodies. Index = dense index; destroying a body
// moves the last body into its place (deterministic, keeps the arrays packed). What every tick
// touches lives here; the parameter records (cold, rarely written) live beside it in World::Impl.
#include <cstdint>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "throng/core/object_id.h"

namespace throng::detail {

// A pair's push last tick, kept by the body with the smaller id for the next tick's warm start.
// The push is float: the crowd solve carries pushes in float anyway, and 8-byte entries make a
// body's eight slots one 64-byte block: with larger entries the lookup of every pair's entry was a
// cache miss, a large share of the pair setup in big crowds (docs/design/solver.md).
struct WarmEntry {
  std::uint32_t partner;  // ObjectId value
  float lambda;
};
inline constexpr std::uint32_t kWarmSlots = 8;

// The push kept for `partner` among a body's first `count` entries, or 0. All eight partners are
// compared at once (SSE2) and only the first `count` matches count: a scan that stopped at the
// match mispredicted its exit for most pairs (a partner's slot is anywhere in 0..count). Entries
// past `count` are stale but initialised; a body keeps at most one entry per partner.
inline float find_warm_push(const WarmEntry* e, std::uint32_t count, std::uint32_t partner) {
  static_assert(sizeof(WarmEntry) == 8 && kWarmSlots == 8, "eight 8-byte slots, one 64-byte block");
#if !defined(__SSE2__)
  for (std::uint32_t q = 0; q < count; ++q) {
    if (e[q].partner == partner) return e[q].lambda;
  }
  return 0.0f;
#else
  // A body without entries (a settled or a sparse crowd) needs no look at its slots at all.
  if (count == 0) return 0.0f;
  const float* f = reinterpret_cast<const float*>(e);
  const __m128 e01 = _mm_loadu_ps(f), e23 = _mm_loadu_ps(f + 4), e45 = _mm_loadu_ps(f + 8), e67 = _mm_loadu_ps(f + 12);
  const __m128i want = _mm_set1_epi32(static_cast<int>(partner));
  const __m128i p0 = _mm_castps_si128(_mm_shuffle_ps(e01, e23, _MM_SHUFFLE(2, 0, 2, 0)));
  const __m128i p1 = _mm_castps_si128(_mm_shuffle_ps(e45, e67, _MM_SHUFFLE(2, 0, 2, 0)));
  const unsigned hits = static_cast<unsigned>(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(p0, want)))) |
                        (static_cast<unsigned>(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(p1, want)))) << 4);
  const unsigned valid = hits & ((1u << count) - 1u);
  return valid == 0 ? 0.0f : e[__builtin_ctz(valid)].lambda;
#endif
}

// The push pair (a, b) (solver indices) kept last tick: the body with the smaller id owns the
// entry (order maps solver to dense indices, where the entries live). The owner is picked by
// selects: which id is smaller is a coin toss in a crowd, and as a branch it mispredicted for half
// the pairs of a search.
inline float kept_pair_push(const std::uint32_t* id, const std::uint32_t* order, const WarmEntry* warm,
                            const std::uint8_t* warm_count, std::uint32_t a, std::uint32_t b) {
  const std::uint32_t id_a = id[a], id_b = id[b];
  const bool a_owns = id_a < id_b;
  const std::uint32_t owner = order[a_owns ? a : b];
  return find_warm_push(warm + std::size_t{owner} * kWarmSlots, warm_count[owner], a_owns ? id_b : id_a);
}

struct BodyStore {
  std::vector<double> x, y, z;        // centre [m]
  std::vector<double> vx, vy, vz;     // desired velocity [m/s] (an input)
  std::vector<double> ax, ay, az;     // actual velocity over the last tick [m/s]
  std::vector<double> push_x, push_y;  // solver push of the last tick (final - moved) [m]
  std::vector<double> r, hh;          // radius, half height of the core segment [m]
  std::vector<std::uint8_t> grounded;
  std::vector<ObjectId> id;
  // Push coefficients from the policy, refreshed when parameters change.
  std::vector<double> resistance;
  std::vector<std::uint32_t> rule_lhs, rule_rhs, group, mask;
  std::vector<std::uint8_t> coeff_dirty;
  std::vector<std::int8_t> morale_level;  // -1 low, 0 normal, +1 high
  std::vector<WarmEntry> warm;            // kWarmSlots per body
  std::vector<std::uint8_t> warm_count;

  std::size_t size() const { return x.size(); }

  // Calls f(column_of_a, column_of_b) for every per-body column of two stores; the one list of
  // columns that resizing, removal, permutation and hashing all go through.
  template <class F>
  static void zip_columns(BodyStore& a, BodyStore& b, F&& f) {
    f(a.x, b.x); f(a.y, b.y); f(a.z, b.z); f(a.vx, b.vx); f(a.vy, b.vy); f(a.vz, b.vz);
    f(a.ax, b.ax); f(a.ay, b.ay); f(a.az, b.az); f(a.push_x, b.push_x); f(a.push_y, b.push_y); f(a.r, b.r); f(a.hh, b.hh);
    f(a.grounded, b.grounded); f(a.id, b.id); f(a.resistance, b.resistance); f(a.rule_lhs, b.rule_lhs);
    f(a.rule_rhs, b.rule_rhs); f(a.group, b.group); f(a.mask, b.mask); f(a.coeff_dirty, b.coeff_dirty);
    f(a.morale_level, b.morale_level); f(a.warm_count, b.warm_count);
  }
  template <class F>
  void for_each_column(F&& f) {
    zip_columns(*this, *this, [&](auto& col, auto&) { f(col); });
  }
  // Read-only walk (checkpoints): the same column list, nothing is modified.
  template <class F>
  void for_each_column(F&& f) const {
    const_cast<BodyStore*>(this)->for_each_column([&](const auto& col) { f(col); });
  }

  // Rebuilds this store in `order` (new index s holds old body order[s]) using `scratch` as the
  // destination, then swaps: no allocation once scratch has reached the store's size.
  void permute(const std::vector<std::uint32_t>& order, BodyStore& scratch) {
    zip_columns(scratch, *this, [&](auto& dst, auto& src) {
      dst.resize(src.size());
      for (std::size_t s = 0; s < order.size(); ++s) dst[s] = src[order[s]];
      dst.swap(src);
    });
    scratch.warm.resize(warm.size());
    for (std::size_t s = 0; s < order.size(); ++s) {
      for (std::uint32_t k = 0; k < kWarmSlots; ++k) scratch.warm[s * kWarmSlots + k] = warm[order[s] * kWarmSlots + k];
    }
    scratch.warm.swap(warm);
  }

  void push_back_default() {
    for_each_column([](auto& col) { col.emplace_back(); });
    warm.resize(warm.size() + kWarmSlots);
  }
  // Moves the last body into slot i and shrinks by one.
  void swap_remove(std::size_t i) {
    const std::size_t last = size() - 1;
    for_each_column([&](auto& col) { col[i] = col[last]; col.pop_back(); });
    for (std::uint32_t k = 0; k < kWarmSlots; ++k) warm[i * kWarmSlots + k] = warm[last * kWarmSlots + k];
    warm.resize(warm.size() - kWarmSlots);
  }
};

}  // namespace throng::detail
