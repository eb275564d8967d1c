// Pile relief: spreading bodies that stand far more densely than they could ever fit.
//
// Why: when thousands of bodies start at one point (a spawn bug, a teleport, a test), the contact
// graph is complete: N^2 pairs, every one 2r deep, and no pair-by-pair solver can untangle it in
// bounded time — a capped broadphase only sees a fraction of the pairs and the pile creeps apart
// over hundreds of ticks. A cell of the finest grid level holds at most a handful of bodies when
// they do not overlap, so a cell with many times that is a pile, not a crowd: its bodies are laid
// out on a Vogel (sunflower) spiral around their centroid, nearest-to-centre first, which is
// overlap-free within the pile and about as compact as a hexagonal packing. The ordinary solver
// takes over from there. Deterministic: ranks are by distance then id, the spiral is fixed.
#include <algorithm>
#include <cmath>

#include "world/world_impl.h"

namespace throng {
namespace {

// 2*pi / phi^2: successive points of the spiral are a golden angle apart.
constexpr double kGoldenAngle = 2.39996322972865332;
// Spiral spacing in body diameters: points fill pi*c^2 each, hexagonal disks sqrt(3)/2*D^2, so
// c = 0.525 D is as dense as a hexagonal packing; 0.6 leaves a little room for the spiral's
// irregular neighbour distances.
constexpr double kSpacingOverDiameter = 0.6;

}  // namespace

bool World::Impl::relieve_piles() {
  const double cell = grid_cell0;
  bool any = false;
  grid.for_each_crowded_cell(kPileThreshold, [&](std::uint32_t begin, std::uint32_t end) {
    const std::vector<std::uint32_t>& order = grid.order();
    pile.clear();
    double cx = 0.0, cy = 0.0, max_r = 0.0;
    for (std::uint32_t s = begin; s < end; ++s) {
      const std::uint32_t i = order[s];
      cx += bodies.x[i];
      cy += bodies.y[i];
      max_r = std::max(max_r, bodies.r[i]);
    }
    const double count = static_cast<double>(end - begin);
    cx /= count;
    cy /= count;
    // Only a real pile: more bodies than could stand in the cell without overlapping 4x over.
    const double capacity = (cell * cell) / (3.14159265358979 * max_r * max_r);
    if (count < 4.0 * capacity) return;
    for (std::uint32_t s = begin; s < end; ++s) {
      const std::uint32_t i = order[s];
      const double dx = bodies.x[i] - cx, dy = bodies.y[i] - cy;
      pile.push_back({dx * dx + dy * dy, bodies.id[i].value, i});
    }
    std::sort(pile.begin(), pile.end(), [](const PileEntry& a, const PileEntry& b) {
      return a.dist2 != b.dist2 ? a.dist2 < b.dist2 : a.id < b.id;
    });
    const double c = kSpacingOverDiameter * 2.0 * max_r;
    for (std::size_t k = 0; k < pile.size(); ++k) {
      const double radius = c * std::sqrt(static_cast<double>(k) + 0.5);
      const double angle = kGoldenAngle * static_cast<double>(k);
      const std::uint32_t i = pile[k].dense;
      bodies.x[i] = cx + radius * std::cos(angle);
      bodies.y[i] = cy + radius * std::sin(angle);
      bodies.warm_count[i] = 0;
    }
    stats.pile_relief_bodies += static_cast<std::uint32_t>(pile.size());
    any = true;
  });
  return any;
}

}  // namespace throng
