#pragma once
// A uniform grid over points for radius queries (morale counts, metrics). Built by a stable radix
// sort of row-major cell keys: deterministic, O(N), no allocation after warm-up. Queries visit the
// 3x3 cells around a point (cell edge = query radius), in key order.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "broadphase/cell_key.h"
#include "broadphase/radix_sort.h"

namespace throng::detail {

class PointGrid {
 public:
  void build(const double* x, const double* y, std::size_t n, double cell_m) {
    inv_cell_ = 1.0 / cell_m;
    items_.resize(n);
    for (std::size_t i = 0; i < n; ++i) items_[i] = {key(coord(x[i]), coord(y[i])), static_cast<std::uint32_t>(i)};
    radix_sort(items_, scratch_);
    cells_.clear();
    for (std::uint32_t k = 0; k < items_.size(); ++k) {
      if (cells_.empty() || cells_.back().key != items_[k].key) cells_.push_back({items_[k].key, k, k});
      cells_.back().end = k + 1;
    }
  }

  template <class F>
  void for_each_near(double x, double y, F&& f) const {
    const std::int64_t cx = coord(x), cy = coord(y);
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      const std::uint64_t lo = key(cx - 1, cy + dy), hi = key(cx + 1, cy + dy);
      auto it = std::lower_bound(cells_.begin(), cells_.end(), lo, [](const Cell& c, std::uint64_t k) { return c.key < k; });
      for (; it != cells_.end() && it->key <= hi; ++it) {
        for (std::uint32_t s = it->begin; s < it->end; ++s) f(items_[s].index);
      }
    }
  }

 private:
  struct Cell {
    std::uint64_t key;
    std::uint32_t begin, end;
  };
  std::int64_t coord(double v) const { return cell_coord(v, inv_cell_); }
  static std::uint64_t key(std::int64_t cx, std::int64_t cy) { return packed_cell_key(cx, cy); }
  double inv_cell_ = 1.0;
  std::vector<KeyIndex> items_, scratch_;
  std::vector<Cell> cells_;
};

}  // namespace throng::detail
