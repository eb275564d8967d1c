#include "interest_grid.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "throng/core/object_id.h"

namespace throng::match::detail {

namespace {

std::uint8_t quantize_yaw_fast(float yaw) {
  // Same steps as protocol::quantize_yaw (1/256 turn, round to nearest) without libm calls.
  constexpr double kStepsPerRad = 256.0 / 6.28318530717958647692;
  const double t = static_cast<double>(yaw) * kStepsPerRad;
  if (!(std::fabs(t) < 1.0e12)) return 0;  // non-finite or absurd
  const auto q = static_cast<std::int64_t>(round_half_even(t));
  return static_cast<std::uint8_t>(q & 0xFF);
}

bool usable(double v) { return std::fabs(v) <= kMaxCoordinateM; }  // false for NaN too

}  // namespace

void InterestGrid::build(const BodyView& b, double cell_m) {
  const std::size_t n = b.id.size();
  if (b.x.size() != n || b.y.size() != n || b.z.size() != n || b.yaw.size() != n)
    throw std::invalid_argument(fmt::format(
        "SnapshotBuilder::index: body spans differ in length (id {}, x {}, y {}, z {}, yaw {})", n, b.x.size(),
        b.y.size(), b.z.size(), b.yaw.size()));
  if (n >= 0xFFFFFFFFu) throw std::invalid_argument("SnapshotBuilder::index: too many bodies");

  // Forget the previous tick (only its own entries of the table: O(bodies), not O(index range)).
  for (std::uint32_t s = 0; s < count_; ++s) present_[ObjectId{pose_[s].id}.index()] = -1;
  count_ = 0;  // no body is indexed until the build completes (an exception leaves it empty)
  min_x_ = min_y_ = max_x_ = max_y_ = 0.0;

  // Pass 1: validate ids, mark indices (-2 = seen this tick), bounding box of the usable bodies.
  body_cell_.resize(n);
  auto unmark = [&](std::size_t upto) {
    for (std::size_t j = 0; j < upto; ++j) present_[ObjectId{b.id[j]}.index()] = -1;
  };
  bool any = false;
  for (std::size_t i = 0; i < n; ++i) {
    const ObjectId oid{b.id[i]};
    if (!oid.valid() || (b.id[i] & ObjectId::kIndexMask) == 0) {
      unmark(i);
      throw std::invalid_argument(fmt::format("SnapshotBuilder::index: body {} has invalid id {}", i, b.id[i]));
    }
    const std::uint32_t idx = oid.index();
    if (idx > ObjectId::kMaxIndex) {
      unmark(i);
      throw std::invalid_argument(fmt::format("SnapshotBuilder::index: body {} id {} has index {} beyond {}", i,
                                              b.id[i], idx, ObjectId::kMaxIndex));
    }
    if (idx >= present_.size()) {
      // Grow with headroom so a slowly growing world does not reallocate every tick.
      const std::size_t grown = std::max<std::size_t>({idx + 1u, present_.size() + present_.size() / 4u, 1024u});
      present_.resize(std::min<std::size_t>(grown, ObjectId::kMaxIndex + 1u), -1);
    }
    if (present_[idx] != -1) {
      unmark(i);
      throw std::invalid_argument(fmt::format(
          "SnapshotBuilder::index: body {} id {} has the same object index {} as another body", i, b.id[i], idx));
    }
    present_[idx] = -2;
    const double x = b.x[i], y = b.y[i];
    if (!usable(x) || !usable(y) || !usable(b.z[i])) {
      body_cell_[i] = ~0u;
      continue;
    }
    body_cell_[i] = 0;
    if (!any) {
      min_x_ = max_x_ = x;
      min_y_ = max_y_ = y;
      any = true;
    } else {
      min_x_ = std::min(min_x_, x);
      max_x_ = std::max(max_x_, x);
      min_y_ = std::min(min_y_, y);
      max_y_ = std::max(max_y_, y);
    }
  }

  // Grid dimensions: cells of cell_m, coarser if the bodies are very spread out.
  const double ex = max_x_ - min_x_, ey = max_y_ - min_y_;
  const double max_cells = std::max(4096.0, 2.0 * static_cast<double>(n));
  cell_ = cell_m > 0.0 ? cell_m : std::max({ex, ey, 1.0}) * 2.0;
  for (;;) {
    const double cx = std::floor(ex / cell_) + 1.0, cy = std::floor(ey / cell_) + 1.0;
    if (cx * cy <= max_cells) {
      nx_ = static_cast<int>(cx);
      ny_ = static_cast<int>(cy);
      break;
    }
    cell_ *= std::max(1.1, std::sqrt(cx * cy / max_cells));
  }
  inv_cell_ = 1.0 / cell_;
  const std::size_t cells = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);

  // Pass 2: counting sort by row-major cell key (stable: input order within a cell).
  // Sized (and written) at once for the most cells this body count allows, not for this tick's
  // extent: a battle's extent keeps growing as routed troops flee, and a table that grew with it
  // reallocated, and took more pages, for as long as the match ran.
  const auto most_cells = static_cast<std::size_t>(max_cells) + 1;
  if (cell_start_.size() < most_cells) cell_start_.assign(most_cells, 0);
  std::fill_n(cell_start_.begin(), cells + 1, 0u);
  std::uint32_t used = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (body_cell_[i] == ~0u) continue;
    const auto key = static_cast<std::uint32_t>(cell_y(b.y[i])) * static_cast<std::uint32_t>(nx_) +
                     static_cast<std::uint32_t>(cell_x(b.x[i]));
    body_cell_[i] = key;
    ++cell_start_[key + 1];
    ++used;
  }
  for (std::size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];

  if (pose_.size() < used) {  // grow only: the arrays are overwritten below, never cleared
    pose_.resize(used);
    z_mm_.resize(used);
    x_.resize(used);
    y_.resize(used);
    z_.resize(used);
    yaw_q_.resize(used);
  }
  // cell_start_[c] doubles as the write cursor of cell c, then is restored by the shift below.
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t idx = ObjectId{b.id[i]}.index();
    const std::uint32_t key = body_cell_[i];
    if (key == ~0u) {
      present_[idx] = -1;
      continue;
    }
    const std::uint32_t s = cell_start_[key]++;
    x_[s] = b.x[i];
    y_[s] = b.y[i];
    z_[s] = b.z[i];
    const auto zmm = static_cast<std::int32_t>(round_half_even(b.z[i] * 1000.0));
    pose_[s] = SlotPose{static_cast<std::int32_t>(round_half_even(b.x[i] * 1000.0)),
                        static_cast<std::int32_t>(round_half_even(b.y[i] * 1000.0)), std::clamp(zmm, -kMaxZQ, kMaxZQ),
                        b.id[i]};
    z_mm_[s] = zmm;
    yaw_q_[s] = quantize_yaw_fast(b.yaw[i]);
    present_[idx] = static_cast<std::int32_t>(s);
  }
  // After the scatter cell_start_[c] is the end of cell c = the start of c + 1: shift back.
  for (std::size_t c = cells; c > 0; --c) cell_start_[c] = cell_start_[c - 1];
  cell_start_[0] = 0;
  count_ = used;
}

}  // namespace throng::match::detail
