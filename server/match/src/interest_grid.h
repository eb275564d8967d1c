#pragma once
// The per-tick spatial index behind SnapshotBuilder: the bodies copied into a uniform 2D grid in
// row-major cell order (counting sort, stable in input order, so the layout depends only on the
// input), plus a table object index -> slot. Private to throng::match.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "throng/match/snapshot_builder.h"

namespace throng::match::detail {

// Round half to even, exactly like std::nearbyint in the default rounding mode, without a libm
// call (baseline x86-64 has no roundsd). Valid for |v| < 2^51; callers stay far below.
inline double round_half_even(double v) {
  constexpr double kMagic = 6755399441055744.0;  // 1.5 * 2^52: the ulp is 1 from 2^52 to 2^53
  return (v + kMagic) - kMagic;
}

// Coordinates beyond this (metres) are not indexed: their millimetres would not fit in int32.
inline constexpr double kMaxCoordinateM = 1.0e6;

// Height limit of the 1 mm quantization (int16 offsets): SlotPose::z is clamped to it.
inline constexpr std::int32_t kMaxZQ = 32767;

// A body's pose rounded to millimetres, laid out like the client-copy record the snapshot loop
// compares it with (one 16-byte load each). z is clamped to +-kMaxZQ (what a client decodes at
// 1 mm); the unclamped height is InterestGrid::z_mm().
struct alignas(16) SlotPose {
  std::int32_t x, y, z;
  std::uint32_t id;
};
static_assert(sizeof(SlotPose) == 16);

class InterestGrid {
 public:
  // Rebuilds the index. cell_m > 0: uniform grid of about that cell size (grown if the bodies are
  // so spread out that the cell count would exceed max(4096, 2 * bodies)); cell_m == 0: one cell.
  // Bodies with a non-finite or > kMaxCoordinateM coordinate are left out. Throws
  // std::invalid_argument on spans of different lengths, id 0, an index beyond ObjectId::kMaxIndex
  // or two bodies with the same index.
  void build(const BodyView& bodies, double cell_m);

  std::uint32_t size() const { return count_; }
  // 1 + the largest object index seen in any build (the size per-object tables need).
  std::uint32_t index_bound() const { return static_cast<std::uint32_t>(present_.size()); }
  // Slot of the body with this object index this tick, or -1.
  std::int32_t slot_of(std::uint32_t object_index) const {
    return object_index < present_.size() ? present_[object_index] : -1;
  }

  // Bodies in slot order: pose in mm (round(v * 1000), z clamped) with the id, the height in mm
  // unclamped, the exact position in metres, yaw in 1/256 turn.
  const SlotPose* pose() const { return pose_.data(); }
  const std::int32_t* z_mm() const { return z_mm_.data(); }
  const double* x() const { return x_.data(); }
  const double* y() const { return y_.data(); }
  const double* z() const { return z_.data(); }
  const std::uint8_t* yaw_q() const { return yaw_q_.data(); }

  // Bounding box of the indexed bodies (all 0 when there are none).
  double min_x() const { return min_x_; }
  double min_y() const { return min_y_; }
  double max_x() const { return max_x_; }
  double max_y() const { return max_y_; }
  double cell_m() const { return cell_; }

  // Calls f(first, end, inner_first, inner_end) for runs of slots [first, end) that hold every
  // body within r of (cx, cy) (and some outside it: the caller tests the distance). One run per
  // grid row. [inner_first, inner_end) is the part of the run in cells that lie entirely within
  // r_inner (no distance test needed there); inner_first == inner_end when there are none. Cells
  // are assigned on the exact positions: a caller testing rounded positions adds the rounding to
  // r and takes it off r_inner.
  template <class F>
  void for_each_run(double cx, double cy, double r, double r_inner, F&& f) const {
    if (count_ == 0) return;
    if (cx + r < min_x_ || cx - r > max_x_ || cy + r < min_y_ || cy - r > max_y_) return;
    constexpr double kSlack = 1e-6;  // positions near a cell boundary may round either way
    const int iy0 = cell_y(cy - r);
    const int iy1 = cell_y(cy + r);
    for (int iy = iy0; iy <= iy1; ++iy) {
      // Smallest |y - cy| a body in this row can have (with a little slack for rounding at the
      // row boundaries), then the x extent of the circle at that height.
      const double row_y0 = min_y_ + iy * cell_;
      const double row_y1 = row_y0 + cell_;
      double dy = cy < row_y0 ? row_y0 - cy : (cy > row_y1 ? cy - row_y1 : 0.0);
      dy = dy > kSlack ? dy - kSlack : 0.0;
      if (dy > r) continue;
      const double w = std::sqrt(r * r - dy * dy);
      const int ix0 = cell_x(cx - w);
      const int ix1 = cell_x(cx + w);
      const std::size_t row = static_cast<std::size_t>(iy) * static_cast<std::size_t>(nx_);
      const std::uint32_t a = cell_start_[row + static_cast<std::size_t>(ix0)];
      const std::uint32_t b = cell_start_[row + static_cast<std::size_t>(ix1) + 1];
      if (a >= b) continue;
      // Cells entirely inside r_inner: the row's largest |y - cy| and the x extent at it.
      std::uint32_t ia = a, ib = a;
      const double dy_far = std::max(std::fabs(row_y0 - cy), std::fabs(row_y1 - cy)) + kSlack;
      if (r_inner > 0.0 && dy_far < r_inner) {
        const double wi = std::sqrt(r_inner * r_inner - dy_far * dy_far) - kSlack;
        // First cell starting at or after cx - wi, last cell ending at or before cx + wi.
        const double f0 = std::ceil((cx - wi - min_x_) * inv_cell_);
        const double f1 = std::floor((cx + wi - min_x_) * inv_cell_) - 1.0;
        const int jx0 = std::max(ix0, f0 > 0.0 ? (f0 < nx_ ? static_cast<int>(f0) : nx_) : 0);
        const int jx1 = std::min(ix1, f1 < nx_ ? (f1 >= -1.0 ? static_cast<int>(f1) : -1) : nx_ - 1);
        if (jx0 <= jx1) {
          ia = cell_start_[row + static_cast<std::size_t>(jx0)];
          ib = cell_start_[row + static_cast<std::size_t>(jx1) + 1];
        }
      }
      f(a, b, ia, ib);
    }
  }

 private:
  int cell_x(double v) const { return clamp_cell((v - min_x_) * inv_cell_, nx_); }
  int cell_y(double v) const { return clamp_cell((v - min_y_) * inv_cell_, ny_); }
  static int clamp_cell(double c, int n) {
    if (!(c > 0.0)) return 0;  // also NaN
    if (c >= static_cast<double>(n - 1)) return n - 1;
    return static_cast<int>(c);  // c >= 0: truncation is floor
  }

  std::uint32_t count_ = 0;  // bodies indexed this tick (the slot arrays may be longer)
  std::vector<SlotPose> pose_;
  std::vector<std::int32_t> z_mm_;
  std::vector<double> x_, y_, z_;
  std::vector<std::uint8_t> yaw_q_;
  std::vector<std::int32_t> present_;
  std::vector<std::uint32_t> cell_start_;  // nx * ny + 1
  std::vector<std::uint32_t> body_cell_;   // scratch: cell of each input body (or ~0u: left out)
  double min_x_ = 0, min_y_ = 0, max_x_ = 0, max_y_ = 0;
  double cell_ = 1, inv_cell_ = 1;
  int nx_ = 1, ny_ = 1;
};

}  // namespace throng::match::detail
