#pragma once
// Grid cell coordinates and a sparse row-major cell key, shared by every grid in the engine (the
// broadphase levels, the morale point grid, the scenery-proximity cells), so that they all agree on
// how a position maps to a cell. Coordinates are clamped to +-2^30 cells so that any finite
// position, however far, gives a valid key.
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace throng::detail {

inline constexpr double kCellCoordLimit = 1073741824.0;  // 2^30

// floor(clamp(v * inv_cell)), which is clamp(floor(v * inv_cell)) for integer bounds. The floor is
// truncation, less one where truncation rounded up (exact within the bounds): std::floor is a
// library call without SSE4.1, and the scenery and morale grids ask for cells of every body
// several times a tick.
inline std::int64_t cell_coord(double v, double inv_cell) {
  const double a = std::clamp(v * inv_cell, -kCellCoordLimit, kCellCoordLimit);
  const auto t = static_cast<std::int64_t>(a);
  return t - static_cast<std::int64_t>(static_cast<double>(t) > a);
}

// Row-major: rows (y) in the high 32 bits, so sorting keys sorts cells row by row.
inline std::uint64_t packed_cell_key(std::int64_t cx, std::int64_t cy) {
  return (static_cast<std::uint64_t>(cy + (std::int64_t{1} << 31)) << 32) |
         static_cast<std::uint64_t>(cx + (std::int64_t{1} << 31));
}

}  // namespace throng::detail
