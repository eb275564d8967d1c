#include "broadphase/hier_grid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <type_traits>

#include <emmintrin.h>

#include "broadphase/cell_key.h"

namespace throng::detail {

// The narrow candidate test: expanded circles in the plane, then the gap between the vertical
// core segments. Pass-through bodies never collide: both masks must accept the other's group.
//   reach = r_i + r_j + margin; candidate iff !(dx^2 + dy^2 >= reach^2)
//   and !(|z_j - z_i| - hh_i - hh_j >= reach) and (group_i & mask_j) != 0 and (group_j & mask_i) != 0
// Every scan below evaluates exactly these operations (negated >=, so a NaN compares as before)
// without branching on the outcome: it writes each tested pair to out[count] and advances count
// only for candidates (in a packed crowd the distance test is close to a coin toss).
struct GridScanBodies {
  const double* __restrict x;
  const double* __restrict y;
  const double* __restrict z;
  const double* __restrict r;
  const double* __restrict hh;
  const std::uint32_t* __restrict group;
  const std::uint32_t* __restrict mask;
};

// Which pair tests a scan makes. kFull: distance, height gap, group/mask. kFlat: every body has
// the same finite z and hh, the same group, a mask accepting that group, and the height gap test
// passes for the smallest possible reach (checked by test_mode), so the gap and group/mask tests
// pass for every pair and only the distance test is made. kFlatOneRadius: kFlat and every body has
// the same radius, so every pair's reach (ri + rj) + margin is the same number.
enum class GridTestMode { kFull, kFlat, kFlatOneRadius };

namespace {



template <GridTestMode kMode>
inline std::size_t scan_one(const GridScanBodies& v, std::uint32_t i, std::uint32_t j, double xi, double yi, double zi,
                            double ri, double hhi, std::uint32_t gi, std::uint32_t mi, double margin,
                            CandidatePair* __restrict out, std::size_t count) {
  const double dx = v.x[j] - xi;
  const double dy = v.y[j] - yi;
  const double reach = ri + (kMode == GridTestMode::kFlatOneRadius ? ri : v.r[j]) + margin;
  if constexpr (kMode != GridTestMode::kFull) {
    out[count] = CandidatePair(i, j);
    return count + static_cast<bool>(!(dx * dx + dy * dy >= reach * reach));
  }
  const double gap_z = std::fabs(v.z[j] - zi) - hhi - v.hh[j];
  const bool hit = static_cast<bool>(!(dx * dx + dy * dy >= reach * reach) & !(gap_z >= reach) &
                                     ((gi & v.mask[j]) != 0) & ((v.group[j] & mi) != 0));
  out[count] = CandidatePair(i, j);
  return count + hit;
}

// Two bodies at a time with SSE2 (baseline x86-64; the same IEEE double operations as the scalar
// code, lane by lane, no FMA), then at most one scalar.
template <GridTestMode kMode>
inline std::size_t scan_range(const GridScanBodies& v, std::uint32_t i, std::uint32_t from, std::uint32_t len, double margin,
                              CandidatePair* __restrict out, std::size_t count) {
  const double xi = v.x[i], yi = v.y[i], zi = v.z[i], ri = v.r[i], hhi = v.hh[i];
  const std::uint32_t gi = v.group[i], mi = v.mask[i];
  const std::uint32_t end = from + len;
  std::uint32_t j = from;
  if (len >= 2) {
    const __m128d vxi = _mm_set1_pd(xi), vyi = _mm_set1_pd(yi), vzi = _mm_set1_pd(zi), vri = _mm_set1_pd(ri);
    const __m128d vhhi = _mm_set1_pd(hhi), vmargin = _mm_set1_pd(margin), sign = _mm_set1_pd(-0.0);
    const __m128i vgi = _mm_set1_epi32(static_cast<int>(gi)), vmi = _mm_set1_epi32(static_cast<int>(mi));
    const __m128i zero = _mm_setzero_si128();
    const double reach1 = ri + ri + margin;
    const __m128d reach1_sq = _mm_set1_pd(reach1 * reach1);
    for (; j + 2 <= end; j += 2) {
      const __m128d dx = _mm_sub_pd(_mm_loadu_pd(v.x + j), vxi);
      const __m128d dy = _mm_sub_pd(_mm_loadu_pd(v.y + j), vyi);
      const __m128d d2 = _mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy));
      int bits;
      if constexpr (kMode == GridTestMode::kFlatOneRadius) {
        bits = _mm_movemask_pd(_mm_cmpnge_pd(d2, reach1_sq));
      } else {
        const __m128d reach = _mm_add_pd(_mm_add_pd(vri, _mm_loadu_pd(v.r + j)), vmargin);
        if constexpr (kMode == GridTestMode::kFlat) {
          bits = _mm_movemask_pd(_mm_cmpnge_pd(d2, _mm_mul_pd(reach, reach)));
        } else {
          const __m128d gap_z = _mm_sub_pd(
              _mm_sub_pd(_mm_andnot_pd(sign, _mm_sub_pd(_mm_loadu_pd(v.z + j), vzi)), vhhi), _mm_loadu_pd(v.hh + j));
          const __m128d near = _mm_and_pd(_mm_cmpnge_pd(d2, _mm_mul_pd(reach, reach)), _mm_cmpnge_pd(gap_z, reach));
          const __m128i gj = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(v.group + j));
          const __m128i mj = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(v.mask + j));
          const __m128i refused = _mm_or_si128(_mm_cmpeq_epi32(_mm_and_si128(vgi, mj), zero),
                                               _mm_cmpeq_epi32(_mm_and_si128(gj, vmi), zero));
          bits = _mm_movemask_pd(_mm_andnot_pd(_mm_castsi128_pd(_mm_unpacklo_epi32(refused, refused)), near));
        }
      }
      out[count] = CandidatePair(i, j);
      count += static_cast<std::size_t>(bits & 1);
      out[count] = CandidatePair(i, j + 1);
      count += static_cast<std::size_t>(bits >> 1);
    }
  }
  if (j < end) count = scan_one<kMode>(v, i, j, xi, yi, zi, ri, hhi, gi, mi, margin, out, count);
  return count;
}

// Which tests the n bodies need (see GridTestMode); any NaN or infinity among z, hh, r gives kFull.
// One SSE2 pass, two bodies per step.
inline GridTestMode test_mode(const GridScanBodies& v, std::size_t n, double margin) {
  if (n == 0) return GridTestMode::kFull;
  const double z0 = v.z[0], hh0 = v.hh[0], r0 = v.r[0];
  const std::uint32_t g0 = v.group[0];
  const __m128d vz0 = _mm_set1_pd(z0), vhh0 = _mm_set1_pd(hh0), vr0 = _mm_set1_pd(r0);
  const __m128i vg0 = _mm_set1_epi32(static_cast<int>(g0)), zero = _mm_setzero_si128();
  __m128d same = _mm_castsi128_pd(_mm_set1_epi32(-1)), one_radius = same;
  __m128d r_min = vr0;
  __m128i refused = zero;
  std::size_t s = 0;
  for (; s + 2 <= n; s += 2) {
    const __m128d r = _mm_loadu_pd(v.r + s);
    same = _mm_and_pd(same, _mm_and_pd(_mm_and_pd(_mm_cmpeq_pd(_mm_loadu_pd(v.z + s), vz0),
                                                  _mm_cmpeq_pd(_mm_loadu_pd(v.hh + s), vhh0)),
                                       _mm_cmpord_pd(r, r)));
    one_radius = _mm_and_pd(one_radius, _mm_cmpeq_pd(r, vr0));
    r_min = _mm_min_pd(r_min, r);
    const __m128i g = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(v.group + s));
    const __m128i m = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(v.mask + s));
    refused = _mm_or_si128(refused, _mm_or_si128(_mm_xor_si128(g, vg0), _mm_cmpeq_epi32(_mm_and_si128(m, vg0), zero)));
  }
  bool ok = _mm_movemask_pd(same) == 3 && _mm_movemask_epi8(_mm_cmpeq_epi32(_mm_unpacklo_epi64(refused, zero), zero)) == 0xFFFF;
  bool all_one_radius = _mm_movemask_pd(one_radius) == 3;
  double rm = std::min(_mm_cvtsd_f64(r_min), _mm_cvtsd_f64(_mm_unpackhi_pd(r_min, r_min)));
  for (; s < n; ++s) {
    ok = ok && v.z[s] == z0 && v.hh[s] == hh0 && v.r[s] == v.r[s] && v.group[s] == g0 && (g0 & v.mask[s]) != 0;
    all_one_radius = all_one_radius && v.r[s] == r0;
    rm = std::min(rm, v.r[s]);
  }
  if (!ok || !std::isfinite(z0) || !std::isfinite(hh0)) return GridTestMode::kFull;
  // Every pair's gap is (|z0 - z0| - hh0) - hh0 and its reach (ri + rj) + margin is at least
  // (r_min + r_min) + margin (rounding is monotone).
  const double gap0 = std::fabs(z0 - z0) - hh0 - hh0;
  if (!(gap0 < rm + rm + margin)) return GridTestMode::kFull;
  return all_one_radius ? GridTestMode::kFlatOneRadius : GridTestMode::kFlat;
}

}  // namespace

std::uint64_t HierGrid::level_key(const Level& lv, std::int64_t cx, std::int64_t cy) {
  const auto col = static_cast<std::uint64_t>(
      std::clamp<std::int64_t>(cx - lv.min_cx + 1, 0, static_cast<std::int64_t>(lv.stride) - 1));
  const auto row = static_cast<std::uint64_t>(
      std::clamp<std::int64_t>(cy - lv.min_cy + 1, 0, static_cast<std::int64_t>(lv.rows) - 1));
  return row * lv.stride + col;
}

void HierGrid::sort_level(Level& lv, const std::int32_t* cxy, const std::uint32_t* idx, std::uint32_t m,
                          std::int64_t min_cx, std::int64_t min_cy, std::int64_t max_cx, std::int64_t max_cy) {
  lv.min_cx = min_cx;
  lv.min_cy = min_cy;
  lv.stride = static_cast<std::uint64_t>(max_cx - min_cx) + 3;
  lv.rows = static_cast<std::uint64_t>(max_cy - min_cy) + 3;
  const std::uint64_t key_count = lv.stride * lv.rows;
  // Stable counting sort by cell key when the key range is at most a few times the body count:
  // one pass to count, one to scatter, and the cell list falls out of the counts. Equal keys keep
  // the dense order, so the result is the stable radix sort's, exactly.
  if (lv.stride <= (std::uint64_t{1} << 32) && lv.rows <= (std::uint64_t{1} << 32) &&
      key_count <= 8 * std::uint64_t{m} + 4096) {
    const auto kc = static_cast<std::uint32_t>(key_count);
    const auto stride = static_cast<std::uint32_t>(lv.stride);
    const auto ox = static_cast<std::uint32_t>(min_cx) - 1u, oy = static_cast<std::uint32_t>(min_cy) - 1u;
    keys_.resize(m);
    if (lv.start.size() < std::size_t{kc} + 2) lv.start.resize(std::size_t{kc} + 2);
    std::uint32_t* cnt = lv.start.data();
    std::fill(cnt, cnt + kc + 2, 0u);
    std::uint32_t* keys = keys_.data();
    // Coordinates are inside the box: the key arithmetic cannot wrap.
    for (std::uint32_t t = 0; t < m; ++t) {
      const std::uint32_t key =
          (static_cast<std::uint32_t>(cxy[2 * t + 1]) - oy) * stride + (static_cast<std::uint32_t>(cxy[2 * t]) - ox);
      keys[t] = key;
      ++cnt[key + 2];
    }
    // Prefix sums: cnt[k + 1] = first slot of key k (the scatter advances it to the first slot of
    // key k + 1). The cell list is read off in the same pass: key k holds [cnt[k + 1], cnt[k + 2]).
    lv.cells.resize(std::size_t{m} + 1);  // one spare: every key writes a cell, occupied or not
    Cell* cells = lv.cells.data();
    std::uint32_t nc = 0;
    std::uint32_t run = lv.begin;
    cnt[1] = run;
    for (std::uint32_t k = 0; k < kc; ++k) {
      const std::uint32_t b = run, c = cnt[k + 2];
      run = b + c;
      cnt[k + 2] = run;
      cells[nc] = Cell(k, b, run);
      nc += c != 0;
    }
    std::uint32_t* order = order_.data();
    if (idx == nullptr) {
      for (std::uint32_t t = 0; t < m; ++t) order[cnt[keys[t] + 1]++] = t;
    } else {
      for (std::uint32_t t = 0; t < m; ++t) order[cnt[keys[t] + 1]++] = idx[t];
    }
    cnt[0] = lv.begin;  // now cnt[k] = first slot of key k for every k <= kc
    lv.cells.resize(nc);
    return;
  }
  lv.start.clear();
  items_.resize(m);
  for (std::uint32_t t = 0; t < m; ++t) {
    items_[t] = {level_key(lv, cxy[2 * t], cxy[2 * t + 1]), idx == nullptr ? t : idx[t]};
  }
  radix_sort(items_, scratch_, key_count - 1);
  std::uint32_t s = lv.begin;
  for (std::size_t k = 0; k < items_.size(); ++k, ++s) {
    order_[s] = items_[k].index;
    if (lv.cells.empty() || lv.cells.back().key != items_[k].key) lv.cells.push_back(Cell(items_[k].key, s, s));
    lv.cells.back().end = s + 1;
  }
}

void HierGrid::build(const double* x, const double* y, const double* r, std::size_t n, double margin_m,
                     double cell0_m) {
  if (levels_.size() < kMaxLevels) levels_.resize(kMaxLevels);
  build_margin_m_ = margin_m;
  rest_pending_ = false;
  level_of_.resize(n);
  coords_.resize(2 * n);
  order_.resize(n);
  std::array<std::uint32_t, kMaxLevels> count{};
  // One pass computes the level-0 cell coordinates, their box and the largest reach; if no body is
  // too big for level 0 (the common case) that is all the one-level sort needs. The coordinates of
  // x and y are computed together with SSE2: clamp(floor(v * inv)) is floor(clamp(v * inv)) for
  // integer bounds, and floor is truncation minus one where truncation rounded up (exact in this
  // range); the box is kept as doubles, which hold these integers exactly.
  int top = 0;
  const double inv0 = 1.0 / cell0_m;
  std::int64_t min_cx = INT64_MAX, min_cy = INT64_MAX, max_cx = INT64_MIN, max_cy = INT64_MIN;
  double max_reach = 0.0;
  {
    std::int32_t* coords = coords_.data();
    const __m128d vinv = _mm_set1_pd(inv0), lo = _mm_set1_pd(-kCellCoordLimit), hi = _mm_set1_pd(kCellCoordLimit);
    const __m128d one = _mm_set1_pd(1.0);
    __m128d vmin = _mm_set1_pd(kCellCoordLimit), vmax = _mm_set1_pd(-kCellCoordLimit);
    for (std::size_t i = 0; i < n; ++i) {
      const __m128d a = _mm_min_pd(_mm_max_pd(_mm_mul_pd(_mm_set_pd(y[i], x[i]), vinv), lo), hi);
      const __m128i t = _mm_cvttpd_epi32(a);
      const __m128d tf = _mm_cvtepi32_pd(t);
      const __m128d up = _mm_cmpgt_pd(tf, a);
      const __m128d f = _mm_sub_pd(tf, _mm_and_pd(up, one));
      _mm_storel_epi64(reinterpret_cast<__m128i*>(coords + 2 * i), _mm_cvttpd_epi32(f));
      vmin = _mm_min_pd(vmin, f);
      vmax = _mm_max_pd(vmax, f);
      max_reach = std::max(max_reach, r[i] + margin_m);
    }
    if (n > 0) {
      min_cx = static_cast<std::int64_t>(_mm_cvtsd_f64(vmin));
      min_cy = static_cast<std::int64_t>(_mm_cvtsd_f64(_mm_unpackhi_pd(vmin, vmin)));
      max_cx = static_cast<std::int64_t>(_mm_cvtsd_f64(vmax));
      max_cy = static_cast<std::int64_t>(_mm_cvtsd_f64(_mm_unpackhi_pd(vmax, vmax)));
    }
  }
  // diameter = 2 (r + margin) is monotone in r, so the largest reach decides whether every body
  // fits level 0 (the per-body test below is !(cell0 < diameter) for level 0).
  if (!(cell0_m < 2.0 * max_reach)) {
    count[0] = static_cast<std::uint32_t>(n);
  } else {
    std::uint8_t* level_of = level_of_.data();
    for (std::size_t i = 0; i < n; ++i) {
      const double diameter = 2.0 * (r[i] + margin_m);
      int l = 0;
      double cell = cell0_m;
      while (cell < diameter && l + 1 < kMaxLevels) { cell *= 2.0; ++l; }
      level_of[i] = static_cast<std::uint8_t>(l);
      ++count[l];
      top = std::max(top, l);
    }
  }
  level_count_ = top + 1;
  std::uint32_t offset = 0;
  double cell = cell0_m;
  for (int l = 0; l < level_count_; ++l) {
    Level& lv = levels_[l];
    lv.cell_m = cell;
    lv.max_reach_m = 0.0;
    lv.begin = offset;
    lv.end = offset + count[l];
    lv.cells.clear();
    offset = lv.end;
    cell *= 2.0;
  }
  if (level_count_ == 1) {
    if (n == 0) return;
    levels_[0].max_reach_m = max_reach;
    sort_level(levels_[0], coords_.data(), nullptr, static_cast<std::uint32_t>(n), min_cx, min_cy, max_cx, max_cy);
    return;
  }
  // Several levels: sort each level by cell key. Items keep the dense order for equal keys (stable
  // sort), so the result depends only on positions and the dense order.
  for (int l = 0; l < level_count_; ++l) {
    Level& lv = levels_[l];
    if (lv.begin == lv.end) { lv.start.clear(); continue; }
    const double inv = 1.0 / lv.cell_m;
    const std::uint32_t count_l = lv.end - lv.begin;
    level_index_.resize(count_l);
    min_cx = INT64_MAX; min_cy = INT64_MAX; max_cx = INT64_MIN; max_cy = INT64_MIN;
    std::uint32_t m = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (level_of_[i] != l) continue;
      const std::int64_t cx = cell_coord(x[i], inv), cy = cell_coord(y[i], inv);
      coords_[2 * m] = static_cast<std::int32_t>(cx);
      coords_[2 * m + 1] = static_cast<std::int32_t>(cy);
      min_cx = std::min(min_cx, cx); max_cx = std::max(max_cx, cx);
      min_cy = std::min(min_cy, cy); max_cy = std::max(max_cy, cy);
      level_index_[m] = static_cast<std::uint32_t>(i);
      lv.max_reach_m = std::max(lv.max_reach_m, r[i] + margin_m);
      ++m;
    }
    sort_level(lv, coords_.data(), level_index_.data(), m, min_cx, min_cy, max_cx, max_cy);
  }
}

// find_pairs' output and budgets for one test mode: body i against ranges of solver indices, each
// tested pair written to out[count] ahead of the test (see GridScanBodies). out is grown to its
// capacity first (free: CandidatePair's default constructor does nothing) and cut back to the hits
// at the end, which never releases capacity, so after warm-up no tick allocates.
template <GridTestMode kMode>
class HierGrid::PairScan {
 public:
  struct Range {
    std::uint32_t begin, end;
  };

  PairScan(const GridScanBodies& a, double margin, std::uint32_t max_candidates, std::vector<CandidatePair>& out)
      : a_(a), margin_(margin), max_candidates_(max_candidates), out_(out), count_(out.size()) {
    out_.resize(out_.capacity());
    buf_ = out_.data();
    room_ = out_.size();
  }

  const GridScanBodies& bodies() const { return a_; }
  std::uint32_t max_candidates() const { return max_candidates_; }

  // Body i of a level against [i + 1, near_end) (its own cell's later bodies and the cells to its
  // right) and then the ranges of the rows above, in that order, within max_candidates.
  void same_level(std::uint32_t i, std::uint32_t near_end, const Range* up, int up_count) {
    std::uint32_t budget = max_candidates_;
    const std::uint32_t near_len = std::min(near_end - (i + 1), budget);
    budget -= near_len;
    std::uint32_t up_len[2] = {0, 0};
    for (int u = 0; u < up_count; ++u) {
      up_len[u] = std::min(up[u].end - up[u].begin, budget);
      budget -= up_len[u];
    }
    if (budget == 0) ++capped_;
    reserve(max_candidates_);
    count_ = scan_range<kMode>(a_, i, i + 1, near_len, margin_, buf_, count_);
    for (int u = 0; u < up_count; ++u) count_ = scan_range<kMode>(a_, i, up[u].begin, up_len[u], margin_, buf_, count_);
  }

  // Body i against [from, from + len): a row of a finer level.
  void other_level(std::uint32_t i, std::uint32_t from, std::uint32_t len) {
    reserve(len);
    count_ = scan_range<kMode>(a_, i, from, len, margin_, buf_, count_);
  }

  void count_capped() { ++capped_; }

  // Cuts the output back to the candidates found; returns the bodies whose budget ran out.
  std::uint32_t finish() {
    out_.resize(count_);
    return capped_;
  }

 private:
  void reserve(std::size_t more) {
    if (room_ >= count_ + more) return;
    out_.resize(std::max(count_ + more, 2 * out_.size()));
    buf_ = out_.data();
    room_ = out_.size();
  }

  const GridScanBodies& a_;
  double margin_;
  std::uint32_t max_candidates_;
  std::vector<CandidatePair>& out_;
  CandidatePair* buf_ = nullptr;
  std::size_t room_ = 0;
  std::size_t count_;
  std::uint32_t capped_ = 0;
};

// A counting-sorted level: start[k] is the first body of key k for every key, so the right
// neighbour ends at start[key + 2] and the row above spans [start[key + stride - 1],
// start[key + stride + 2]) (empty cells contribute nothing). Occupied keys are interior, so
// key + stride + 2 <= stride * rows. Two cells out: key + 2 is at worst the next row's empty
// border cell and key - 2 the previous row's, so the ranges still hold only the cells meant; a row
// beyond the last holds nothing.
template <class Scan>
void HierGrid::scan_indexed_level(const Level& lv, std::uint32_t c0, std::uint32_t c1, int reach_cells,
                                  int top_reach, Scan& scan) const {
  const std::uint32_t* start = lv.start.data();
  for (std::uint32_t ci = c0; ci < c1; ++ci) {
    const Cell& c = lv.cells[ci];
    const std::uint64_t k = c.key;
    typename Scan::Range up[2];
    int up_count = 0;
    std::uint32_t near_end;
    if (reach_cells == 1) {
      near_end = start[k + 2];
      up[up_count++] = {start[k + lv.stride - 1], start[k + lv.stride + 2]};
    } else {
      near_end = start[k + 3];
      const std::uint64_t row = k / lv.stride;
      for (std::uint64_t r = 1; r <= 2 && row + r < lv.rows; ++r) {
        const std::uint64_t w = r == 2 ? static_cast<std::uint64_t>(top_reach) : 2;
        up[up_count++] = {start[k + r * lv.stride - w], start[k + r * lv.stride + w + 1]};
      }
    }
    for (std::uint32_t i = c.begin; i < c.end; ++i) scan.same_level(i, near_end, up, up_count);
  }
}

// A radix-sorted (sparse) level: the cell and its right neighbours are adjacent in the sorted
// order, and so are the cells of a row above: contiguous ranges of bodies, scanned in the same
// order as cell by cell.
template <class Scan>
void HierGrid::scan_sorted_level(const Level& lv, std::uint32_t c0, std::uint32_t c1, int reach_cells,
                                 int top_reach, Scan& scan) const {
  const std::vector<Cell>& cells = lv.cells;
  const auto reach = static_cast<std::uint64_t>(reach_cells);
  // How far sideways row r above reaches (the top row of a two-cell search may leave its corners out).
  auto row_reach = [&](int r) { return r == 2 ? static_cast<std::uint64_t>(top_reach) : reach; };
  // First cell at or after (cx - reach, cy + r); only moves forward from the first cell's (a
  // search in pieces starts each piece where the whole search would be at its first cell).
  std::size_t up_at[2] = {0, 0};
  if (c0 < c1) {
    for (int r = 1; r <= reach_cells; ++r) {
      const std::uint64_t up_lo = cells[c0].key + static_cast<std::uint64_t>(r) * lv.stride - row_reach(r);
      up_at[r - 1] = static_cast<std::size_t>(
          std::lower_bound(cells.begin(), cells.end(), up_lo, [](const Cell& cell, std::uint64_t key) { return cell.key < key; }) -
          cells.begin());
    }
  }
  for (std::size_t k = c0; k < c1; ++k) {
    const Cell& c = cells[k];
    std::size_t last = k;
    while (last + 1 < cells.size() && cells[last + 1].key <= c.key + reach) ++last;
    const std::uint32_t near_end = cells[last].end;
    typename Scan::Range up[2];
    int up_count = 0;
    for (int r = 1; r <= reach_cells; ++r) {
      const std::uint64_t up_lo = c.key + static_cast<std::uint64_t>(r) * lv.stride - row_reach(r);
      const std::uint64_t up_hi = c.key + static_cast<std::uint64_t>(r) * lv.stride + row_reach(r);
      std::size_t& u = up_at[r - 1];
      while (u < cells.size() && cells[u].key < up_lo) ++u;
      if (u < cells.size() && cells[u].key <= up_hi) {
        std::size_t q = u;
        while (q + 1 < cells.size() && cells[q + 1].key <= up_hi) ++q;
        up[up_count++] = {cells[u].begin, cells[q].end};
      }
    }
    for (std::uint32_t i = c.begin; i < c.end; ++i) scan.same_level(i, near_end, up, up_count);
  }
}

// Each body of coarser level l queries the finer levels over its box, row by row. The cells of
// one row between two keys hold one contiguous range of bodies, so a row is one range scan; each
// body examines at most 4 * max_candidates bodies in that order (a giant legitimately touches
// many small bodies).
template <class Scan>
void HierGrid::scan_cross_levels(int l, std::uint32_t i0, std::uint32_t i1, double extra, Scan& scan) const {
  const GridScanBodies& a = scan.bodies();
  for (std::uint32_t i = i0; i < i1; ++i) {
    std::uint32_t budget = scan.max_candidates() * 4;
    for (int m = 0; m < l; ++m) {
      const Level& fine = levels_[m];
      if (fine.cells.empty()) continue;
      const double reach = a.r[i] + fine.max_reach_m + extra;
      const double inv = 1.0 / fine.cell_m;
      const std::int64_t cx0 = cell_coord(a.x[i] - reach, inv), cx1 = cell_coord(a.x[i] + reach, inv);
      // Rows outside the level's occupied rows hold no bodies: skip them.
      const std::int64_t max_cy = fine.min_cy + static_cast<std::int64_t>(fine.rows) - 3;
      const std::int64_t cy0 = std::max(cell_coord(a.y[i] - reach, inv), fine.min_cy);
      const std::int64_t cy1 = std::min(cell_coord(a.y[i] + reach, inv), max_cy);
      const std::uint32_t* start = fine.start.empty() ? nullptr : fine.start.data();
      for (std::int64_t cy = cy0; cy <= cy1 && budget > 0; ++cy) {
        const std::uint64_t lo = level_key(fine, cx0, cy), hi = level_key(fine, cx1, cy);
        std::uint32_t row_begin = 0, row_end = 0;
        if (start != nullptr) {
          row_begin = start[lo];
          row_end = start[hi + 1];
        } else {
          auto it = std::lower_bound(fine.cells.begin(), fine.cells.end(), lo,
                                     [](const Cell& cell, std::uint64_t key) { return cell.key < key; });
          if (it != fine.cells.end() && it->key <= hi) {
            row_begin = it->begin;
            while (it + 1 != fine.cells.end() && (it + 1)->key <= hi) ++it;
            row_end = it->end;
          }
        }
        const std::uint32_t len = std::min(row_end - row_begin, budget);
        budget -= len;
        scan.other_level(i, row_begin, len);
      }
    }
    if (budget == 0) scan.count_capped();
  }
}

template <class Scan>
void HierGrid::scan_piece(const SearchPiece& piece, int reach_cells, double extra, Scan& scan) const {
  const Level& lv = levels_[static_cast<std::size_t>(piece.level)];
  // A two-cell search's top row: its corner cells (two columns aside) are at least cell * sqrt(2)
  // from any point of the body's cell, beyond every pair of the level when the search margin is
  // small enough (a crowd of one size with a pair list's skin: a sixth of the cells a body
  // examines). Left out only then, with room for the rounding of positions into cells; they hold
  // no pair, so the list is the same.
  const double widest = 2.0 * lv.max_reach_m - build_margin_m_ + extra;
  const int top_reach = reach_cells == 2 && lv.cell_m * std::sqrt(2.0) > widest * (1.0 + 1e-9) + 1e-9 ? 1 : reach_cells;
  if (piece.cross) scan_cross_levels(piece.level, piece.begin, piece.end, extra, scan);
  else if (!lv.start.empty()) scan_indexed_level(lv, piece.begin, piece.end, reach_cells, top_reach, scan);
  else scan_sorted_level(lv, piece.begin, piece.end, reach_cells, top_reach, scan);
}

void HierGrid::cut_pieces(bool on_pool, bool split, double first_share) {
  // The search in order: every level's cells, finest first, then each coarser level's bodies
  // against the finer levels. A body's candidates depend on the grid only, so the search can be
  // cut anywhere between cells (or coarser bodies) and its pieces joined in order.
  pieces_.clear();
  constexpr std::uint32_t kBodiesPerPiece = 4096;
  const double share = std::clamp(first_share, 0.0, 1.0);
  const auto first_bodies = static_cast<std::uint32_t>(share * static_cast<double>(order_.size()));
  rest_begin_ = 0;
  for (int l = 0; l < level_count_; ++l) {
    const Level& lv = levels_[static_cast<std::size_t>(l)];
    const auto cells = static_cast<std::uint32_t>(lv.cells.size());
    // The cut (split): after the finest level's cell holding body first_bodies - 1 (its bodies are
    // the first solver indices), after the whole level if it holds fewer, nowhere if none.
    const bool cut_here = l == 0 && split && first_bodies > 0;
    const std::uint32_t last = cut_here ? std::min(lv.begin + first_bodies, lv.end) : 0;
    std::uint32_t c0 = 0, bodies = 0;
    // On one thread only the cut is looked for: the cells after it are one piece.
    for (std::uint32_t c = 0; c < cells && (on_pool || (cut_here && rest_begin_ == 0)); ++c) {
      bodies += lv.cells[c].end - lv.cells[c].begin;
      const bool at_cut = cut_here && lv.cells[c].begin < last && lv.cells[c].end >= last;
      if ((on_pool && bodies >= kBodiesPerPiece) || at_cut) {
        pieces_.push_back({l, false, c0, c + 1});
        c0 = c + 1;
        bodies = 0;
        if (at_cut) rest_begin_ = pieces_.size();
      }
    }
    if (c0 < cells) pieces_.push_back({l, false, c0, cells});
    if (cut_here && rest_begin_ == 0) rest_begin_ = pieces_.size();
  }
  for (int l = 1; l < level_count_; ++l) {
    const Level& lv = levels_[static_cast<std::size_t>(l)];
    const std::uint32_t step = on_pool ? kBodiesPerPiece / 8 : lv.end - lv.begin;  // a coarse body scans many
    for (std::uint32_t i = lv.begin; i < lv.end; i += std::max(step, 1u)) {
      pieces_.push_back({l, true, i, std::min(lv.end, i + std::max(step, 1u))});
    }
  }
}

template <GridTestMode kMode>
std::uint32_t HierGrid::find_pairs_in_mode(const GridScanBodies& a, double margin, double extra, std::uint32_t max_candidates,
                                           std::vector<CandidatePair>& out, WorkerPool* pool, SearchPart part,
                                           double first_share) {
  // Each body examines at most max_candidates bodies: its own cell's later bodies and the right
  // cell first, then the (up to three) cells of the row above. A search margin wider than the
  // build's (a pair list's skin) reaches two cells: the cell's later bodies and the next two cells,
  // then five cells in each of the two rows above (max_extra_margin says how far that reaches).
  const int reach_cells = extra > 0.0 ? 2 : 1;
  const bool cut = pool != nullptr && pool->threads() > 1;
  if (part == SearchPart::kRest) {
    if (!rest_pending_) throw std::logic_error("HierGrid::find_pairs: the rest of a search that was not begun");
  } else {
    cut_pieces(cut, part == SearchPart::kFirst, first_share);
  }
  rest_pending_ = part == SearchPart::kFirst;
  const std::size_t p0 = part == SearchPart::kRest ? rest_begin_ : 0;
  const std::size_t p1 = part == SearchPart::kFirst ? rest_begin_ : pieces_.size();
  if (!cut || p1 - p0 < 2) {
    PairScan<kMode> scan(a, margin, max_candidates, out);
    for (std::size_t k = p0; k < p1; ++k) scan_piece(pieces_[k], reach_cells, extra, scan);
    return scan.finish();
  }
  const unsigned threads = pool->threads();
  if (thread_out_.size() < threads) thread_out_.resize(threads);
  for (unsigned t = 0; t < threads; ++t) {
    thread_out_[t].clear();
    if (thread_out_[t].capacity() < 2 * largest_search_) thread_out_[t].reserve(2 * largest_search_);
  }
  piece_out_.resize(p1 - p0);
  auto search = [&](std::uint32_t k, unsigned thread) {
    std::vector<CandidatePair>& mine = thread_out_[thread];
    const std::size_t begin = mine.size();
    PairScan<kMode> scan(a, margin, max_candidates, mine);
    scan_piece(pieces_[p0 + k], reach_cells, extra, scan);
    const std::uint32_t capped = scan.finish();
    piece_out_[k] = {thread, begin, mine.size(), capped};
  };
  pool->run(static_cast<std::uint32_t>(p1 - p0), search);
  std::size_t total = 0;
  std::uint32_t capped = 0;
  for (const PieceOut& p : piece_out_) {
    total += p.end - p.begin;
    capped += p.capped;
  }
  largest_search_ = std::max(largest_search_, total);
  std::size_t at = out.size();
  // Twice the room at a new high, as a scan grows its output (resize alone would allocate the
  // exact size at every new high).
  if (out.capacity() < at + total) out.reserve(2 * (at + total));
  out.resize(at + total);
  for (const PieceOut& p : piece_out_) {
    const CandidatePair* from = thread_out_[p.thread].data();
    std::copy(from + p.begin, from + p.end, out.begin() + static_cast<std::ptrdiff_t>(at));
    at += p.end - p.begin;
  }
  return capped;
}

std::uint32_t HierGrid::find_pairs(const GridBodyView& v, double margin, std::uint32_t max_candidates,
                                   std::vector<CandidatePair>& out, WorkerPool* pool, SearchPart part,
                                   double first_share) {
  const GridScanBodies a{v.x, v.y, v.z, v.r, v.hh, v.group, v.mask};
  const double extra = std::max(0.0, margin - build_margin_m_);
  if (level_count_ > 0 && extra > max_extra_margin(levels_[0].cell_m, build_margin_m_)) {
    throw std::invalid_argument("HierGrid::find_pairs: search margin beyond two cells of the grid");
  }
  switch (test_mode(a, order_.size(), margin)) {
    case GridTestMode::kFlatOneRadius: return find_pairs_in_mode<GridTestMode::kFlatOneRadius>(a, margin, extra, max_candidates, out, pool, part, first_share);
    case GridTestMode::kFlat: return find_pairs_in_mode<GridTestMode::kFlat>(a, margin, extra, max_candidates, out, pool, part, first_share);
    case GridTestMode::kFull: break;
  }
  return find_pairs_in_mode<GridTestMode::kFull>(a, margin, extra, max_candidates, out, pool, part, first_share);
}

}  // namespace throng::detail
