#pragma once
// Residual penetration of a crowd, measured independently of the solver.
//
// Why independent: the solver reports its own max_pen_over_radius over the pairs *it* considered
// (candidate caps, margins, early exit). A benchmark that trusted that figure could not catch a
// solver that misses pairs. This code has its own uniform grid over all bodies and the exact 3D
// distance between upright capsules: core distance = sqrt(dxy^2 + gap_z^2), gap_z = the gap
// between the vertical core segments [z - half_height, z + half_height] (0 when they overlap).
//
// Definitions (pen = max(0, r_a + r_b - distance) / min(r_a, r_b)):
//   max_pen_over_radius  max over all pairs
//   p99_pen_over_radius  99th percentile (nearest rank) over bodies of each body's deepest pen
//   pairs_over_1pct      pairs with pen > 0.01
//   nan_count            bodies with a non-finite coordinate (left out of everything else)
//
// Cost is O(N) for a crowd (grid cell = 2 * largest radius, 3x3 neighbourhood). Bodies that share
// exactly the same position and shape (the one_cell scene's start: every body at one point) are
// handled as one class with a multiplicity: within a class every pair is at distance 0, so its
// pen is exactly 2 * r / r = 2 and it holds m(m-1)/2 pairs — counted, not enumerated. Only a
// clump of bodies that are close but not identical still costs O(k^2) per cell; pair_tests
// reports that cost so the caller can warn.
#include <cstdint>
#include <span>

namespace throng {
class World;
}

namespace throng::scene {

struct ResidualStats {
  std::uint64_t bodies = 0;           // bodies measured (finite ones)
  std::uint64_t nan_count = 0;
  double max_pen_over_radius = 0.0;
  double p99_pen_over_radius = 0.0;
  std::uint64_t pairs_over_1pct = 0;
  std::uint64_t pair_tests = 0;       // narrow-phase tests run (cost; quadratic in a dense clump)
  std::uint64_t coincident_bodies = 0;  // bodies sharing an exact position and shape with another
};

struct BodyArrays {
  std::span<const double> x, y, z, radius, half_height;
};

// Penetration of one pair over the smaller radius (0 when apart). Exposed for tests and tools.
double pair_pen_over_radius(double ax, double ay, double az, double ar, double ahh, double bx, double by, double bz,
                            double br, double bhh);

ResidualStats measure_residual(const BodyArrays& bodies);
ResidualStats measure_residual(const World& world);

// max over bodies of World::scenery_max_penetration(i) / radius(i); 0 without scenery.
double static_pen_max_over_radius(const World& world);

}  // namespace throng::scene
