#include "broadphase/hier_grid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "broadphase/cell_key.h"

namespace throng::detail {
namespace {

// The narrow candidate test: expanded circles in the plane, then the gap between the vertical
// core segments. Pass-through bodies never collide: both masks must accept the other's group.
inline bool is_candidate(const GridBodyView& v, std::uint32_t i, std::uint32_t j, double margin) {
  const double dx = v.x[j] - v.x[i];
  const double dy = v.y[j] - v.y[i];
  const double reach = v.r[i] + v.r[j] + margin;
  if (dx * dx + dy * dy >= reach * reach) return false;
  const double gap_z = std::fabs(v.z[j] - v.z[i]) - v.hh[i] - v.hh[j];
  if (gap_z >= reach) return false;
  return (v.group[i] & v.mask[j]) != 0 && (v.group[j] & v.mask[i]) != 0;
}

// Tests body i against bodies [from, from + len) in order, writing every tested pair to out[count]
// and advancing count only for candidates (no branch on the outcome: in a packed crowd the distance
// test is close to a coin toss). out must have room for len more pairs. The arithmetic is
// is_candidate's, term for term, and a NaN compares the same way (the tests are negated >=).
struct BodyArrays {
  const double* __restrict x;
  const double* __restrict y;
  const double* __restrict z;
  const double* __restrict r;
  const double* __restrict hh;
  const std::uint32_t* __restrict group;
  const std::uint32_t* __restrict mask;
};

inline std::size_t scan_range(const BodyArrays& v, std::uint32_t i, std::uint32_t from, std::uint32_t len, double margin,
                              CandidatePair* __restrict out, std::size_t count) {
  const double xi = v.x[i], yi = v.y[i], zi = v.z[i], ri = v.r[i], hhi = v.hh[i];
  const std::uint32_t gi = v.group[i], mi = v.mask[i];
  const std::uint32_t end = from + len;
  for (std::uint32_t j = from; j < end; ++j) {
    const double dx = v.x[j] - xi;
    const double dy = v.y[j] - yi;
    const double reach = ri + v.r[j] + margin;
    const double gap_z = std::fabs(v.z[j] - zi) - hhi - v.hh[j];
    const bool hit = static_cast<bool>(!(dx * dx + dy * dy >= reach * reach) & !(gap_z >= reach) &
                                       ((gi & v.mask[j]) != 0) & ((v.group[j] & mi) != 0));
    out[count] = CandidatePair(i, j);
    count += hit;
  }
  return count;
}

}  // namespace

std::uint64_t HierGrid::level_key(const Level& lv, std::int64_t cx, std::int64_t cy) {
  const auto col = static_cast<std::uint64_t>(
      std::clamp<std::int64_t>(cx - lv.min_cx + 1, 0, static_cast<std::int64_t>(lv.stride) - 1));
  const auto row = static_cast<std::uint64_t>(
      std::clamp<std::int64_t>(cy - lv.min_cy + 1, 0, static_cast<std::int64_t>(lv.rows) - 1));
  return row * lv.stride + col;
}

void HierGrid::build(const double* x, const double* y, const double* r, std::size_t n, double margin_m,
                     double cell0_m) {
  if (levels_.size() < kMaxLevels) levels_.resize(kMaxLevels);
  level_of_.resize(n);
  level_count_ = 1;
  std::array<std::uint32_t, kMaxLevels> count{};
  for (std::size_t i = 0; i < n; ++i) {
    const double diameter = 2.0 * (r[i] + margin_m);
    int l = 0;
    double cell = cell0_m;
    while (cell < diameter && l + 1 < kMaxLevels) { cell *= 2.0; ++l; }
    level_of_[i] = static_cast<std::uint8_t>(l);
    ++count[l];
    level_count_ = std::max(level_count_, l + 1);
  }
  order_.resize(n);
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
  // Sort each level by cell key. Items keep the dense order for equal keys (stable sort), so the
  // result depends only on positions and the dense order.
  for (int l = 0; l < level_count_; ++l) {
    Level& lv = levels_[l];
    if (lv.begin == lv.end) continue;
    const double inv = 1.0 / lv.cell_m;
    const std::uint32_t count_l = lv.end - lv.begin;
    items_.resize(count_l);
    coords_.resize(2 * std::size_t{count_l});
    std::int64_t min_cx = INT64_MAX, min_cy = INT64_MAX, max_cx = INT64_MIN, max_cy = INT64_MIN;
    const bool one_level = level_count_ == 1;  // the common case: no per-body level test
    std::size_t m = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!one_level && level_of_[i] != l) continue;
      const std::int64_t cx = cell_coord(x[i], inv), cy = cell_coord(y[i], inv);
      coords_[2 * m] = cx;
      coords_[2 * m + 1] = cy;
      min_cx = std::min(min_cx, cx); max_cx = std::max(max_cx, cx);
      min_cy = std::min(min_cy, cy); max_cy = std::max(max_cy, cy);
      items_[m] = {0, static_cast<std::uint32_t>(i)};
      lv.max_reach_m = std::max(lv.max_reach_m, r[i] + margin_m);
      ++m;
    }
    lv.min_cx = min_cx;
    lv.min_cy = min_cy;
    lv.stride = static_cast<std::uint64_t>(max_cx - min_cx) + 3;
    lv.rows = static_cast<std::uint64_t>(max_cy - min_cy) + 3;
    for (std::size_t k = 0; k < items_.size(); ++k) items_[k].key = level_key(lv, coords_[2 * k], coords_[2 * k + 1]);
    radix_sort(items_, scratch_, lv.stride * lv.rows - 1);
    std::uint32_t s = lv.begin;
    for (std::size_t k = 0; k < items_.size(); ++k, ++s) {
      order_[s] = items_[k].index;
      if (lv.cells.empty() || lv.cells.back().key != items_[k].key) lv.cells.push_back({items_[k].key, s, s});
      lv.cells.back().end = s + 1;
    }
  }
}

std::uint32_t HierGrid::find_pairs(const GridBodyView& v, double margin, std::uint32_t max_candidates,
                                   std::vector<CandidatePair>& out) const {
  std::uint32_t capped = 0;
  const BodyArrays a{v.x, v.y, v.z, v.r, v.hh, v.group, v.mask};
  // Pairs are written to out[count] ahead of the test; out is grown to its capacity first (free:
  // CandidatePair's default constructor does nothing) and cut back to the hits at the end, which
  // never releases capacity, so after warm-up no tick allocates.
  std::size_t count = out.size();
  out.resize(out.capacity());
  for (int l = 0; l < level_count_; ++l) {
    const std::vector<Cell>& cells = levels_[l].cells;
    const std::uint64_t stride = levels_[l].stride;
    std::size_t up = 0;  // first cell at or after (cx - 1, cy + 1); only moves forward
    for (std::size_t k = 0; k < cells.size(); ++k) {
      const Cell& c = cells[k];
      const std::uint64_t up_lo = c.key + stride - 1, up_hi = c.key + stride + 1;
      while (up < cells.size() && cells[up].key < up_lo) ++up;
      // The cell and its right neighbour are adjacent in the sorted order, and so are the (up
      // to three) cells of the row above: two contiguous ranges of bodies, scanned in the same
      // order as cell by cell.
      const std::uint32_t near_end = (k + 1 < cells.size() && cells[k + 1].key == c.key + 1) ? cells[k + 1].end : c.end;
      std::uint32_t up_begin = 0, up_end = 0;
      if (up < cells.size() && cells[up].key <= up_hi) {
        std::size_t q = up;
        while (q + 1 < cells.size() && cells[q + 1].key <= up_hi) ++q;
        up_begin = cells[up].begin;
        up_end = cells[q].end;
      }
      for (std::uint32_t i = c.begin; i < c.end; ++i) {
        // Each body examines at most max_candidates bodies: its own cell's later bodies and the
        // right cell first, then the row above.
        const std::uint32_t near_len = std::min(near_end - (i + 1), max_candidates);
        const std::uint32_t up_len = std::min(up_end - up_begin, max_candidates - near_len);
        if (near_len + up_len == max_candidates) ++capped;
        if (out.size() < count + near_len + up_len) out.resize(std::max(count + near_len + up_len, 2 * out.size()));
        count = scan_range(a, i, i + 1, near_len, margin, out.data(), count);
        count = scan_range(a, i, up_begin, up_len, margin, out.data(), count);
      }
    }
  }
  out.resize(count);
  // Cross-level pairs: each body of a coarser level queries the finer levels over its box.
  for (int l = 1; l < level_count_; ++l) {
    const Level& lv = levels_[l];
    for (std::uint32_t i = lv.begin; i < lv.end; ++i) {
      std::uint32_t budget = max_candidates * 4;  // a giant legitimately touches many small bodies
      for (int m = 0; m < l; ++m) {
        const Level& fine = levels_[m];
        if (fine.cells.empty()) continue;
        const double reach = v.r[i] + fine.max_reach_m;
        const double inv = 1.0 / fine.cell_m;
        const std::int64_t cx0 = cell_coord(v.x[i] - reach, inv), cx1 = cell_coord(v.x[i] + reach, inv);
        const std::int64_t cy0 = cell_coord(v.y[i] - reach, inv), cy1 = cell_coord(v.y[i] + reach, inv);
        for (std::int64_t cy = cy0; cy <= cy1 && budget > 0; ++cy) {
          const std::uint64_t lo = level_key(fine, cx0, cy), hi = level_key(fine, cx1, cy);
          auto it = std::lower_bound(fine.cells.begin(), fine.cells.end(), lo,
                                     [](const Cell& cell, std::uint64_t key) { return cell.key < key; });
          for (; it != fine.cells.end() && it->key <= hi && budget > 0; ++it) {
            for (std::uint32_t j = it->begin; j < it->end && budget > 0; ++j, --budget) {
              if (is_candidate(v, i, j, margin)) out.push_back({i, j});
            }
          }
        }
      }
      if (budget == 0) ++capped;
    }
  }
  return capped;
}

}  // namespace throng::detail
