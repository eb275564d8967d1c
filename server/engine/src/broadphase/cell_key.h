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

inline std::int64_t cell_coord(double v, double inv_cell) {
  return static_cast<std::int64_t>(std::clamp(std::floor(v * inv_cell), -kCellCoordLimit, kCellCoordLimit));
}

// Row-major: rows (y) in the high 32 bits, so sorting keys sorts cells row by row.
inline std::uint64_t packed_cell_key(std::int64_t cx, std::int64_t cy) {
  return (static_cast<std::uint64_t>(cy + (std::int64_t{1} << 31)) << 32) |
         static_cast<std::uint64_t>(cx + (std::int64_t{1} << 31));
}

}  // namespace throng::detail
