// The independent residual metric gives the penetrations the geometry says, on hand-built cases.
// Values are chosen exactly representable (halves, quarters, 3-4-5 triangles) so equalities are exact.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "throng/scene/residual.h"

namespace throng::scene {
namespace {

struct Bodies {
  std::vector<double> x, y, z, r, hh;
  void add(double px, double py, double pz, double radius, double half_height) {
    x.push_back(px), y.push_back(py), z.push_back(pz), r.push_back(radius), hh.push_back(half_height);
  }
  ResidualStats measure() const { return measure_residual(BodyArrays{x, y, z, r, hh}); }
};

TEST(SceneResidual, TwoSpheresOverlappingByKnownDepth) {
  // r = 0.5 each, centres 0.75 apart: depth 1.0 - 0.75 = 0.25, over the smaller radius 0.5 = 0.5.
  Bodies b;
  b.add(0.0, 0.0, 0.5, 0.5, 0.0);
  b.add(0.75, 0.0, 0.5, 0.5, 0.0);
  const auto s = b.measure();
  EXPECT_EQ(s.max_pen_over_radius, 0.5);
  EXPECT_EQ(s.p99_pen_over_radius, 0.5);
  EXPECT_EQ(s.pairs_over_1pct, 1u);
  EXPECT_EQ(s.nan_count, 0u);
}

TEST(SceneResidual, DifferentRadiiUseTheSmaller) {
  // r 0.25 and 1.0, 1.0 apart horizontally: depth 0.25, over 0.25 = 1.
  Bodies b;
  b.add(0.0, 0.0, 0.0, 0.25, 0.0);
  b.add(0.0, 1.0, 0.0, 1.0, 0.0);
  EXPECT_EQ(b.measure().max_pen_over_radius, 1.0);
}

TEST(SceneResidual, TouchingAndApartAreZero) {
  Bodies b;
  b.add(0.0, 0.0, 0.0, 0.5, 0.0);
  b.add(1.0, 0.0, 0.0, 0.5, 0.0);  // exactly touching
  b.add(5.0, 0.0, 0.0, 0.5, 0.0);
  const auto s = b.measure();
  EXPECT_EQ(s.max_pen_over_radius, 0.0);
  EXPECT_EQ(s.pairs_over_1pct, 0u);
}

TEST(SceneResidual, CapsulesStackedWithVerticalGap) {
  // Core segments [-1, 1] and [1.4, 3.4]: gap_z = 0.4; horizontal offset 0.3 -> distance 0.5.
  // r = 0.5 each: depth 0.5, over 0.5 = 1. The overlap is only there because of the 3D distance:
  // ignoring the gap (2D) would say 0.7 / 0.5; ignoring the offset would say 0.6 / 0.5.
  Bodies b;
  b.add(0.0, 0.0, 0.0, 0.5, 1.0);
  b.add(0.3, 0.0, 2.4, 0.5, 1.0);
  EXPECT_DOUBLE_EQ(b.measure().max_pen_over_radius, 1.0);
  // Raise the top one until the cores are 1.0 apart vertically: no contact.
  b.z[1] = 3.0;
  EXPECT_EQ(b.measure().max_pen_over_radius, 0.0);
}

TEST(SceneResidual, OverlappingCoresUseHorizontalDistanceOnly) {
  // Cores [0, 2] and [1, 3] overlap in z, so distance = horizontal 0.25; depth 0.75 over 0.5.
  Bodies b;
  b.add(0.0, 0.0, 1.0, 0.5, 1.0);
  b.add(0.0, 0.25, 2.0, 0.5, 1.0);
  EXPECT_EQ(b.measure().max_pen_over_radius, 1.5);
}

TEST(SceneResidual, OneCellWithThreeBodies) {
  // Three identical bodies at one point: 3 pairs, each at distance 0, pen = 2r / r = 2.
  Bodies b;
  for (int i = 0; i < 3; ++i) b.add(1.0, 2.0, 0.35, 0.35, 0.0);
  const auto s = b.measure();
  EXPECT_EQ(s.max_pen_over_radius, 2.0);
  EXPECT_EQ(s.p99_pen_over_radius, 2.0);
  EXPECT_EQ(s.pairs_over_1pct, 3u);
  EXPECT_EQ(s.coincident_bodies, 3u);
}

TEST(SceneResidual, OneCellAtScaleIsCountedNotEnumerated) {
  // 100,000 bodies at one point: C(n, 2) pairs, found without n^2 / 2 tests.
  Bodies b;
  const std::uint64_t n = 100'000;
  for (std::uint64_t i = 0; i < n; ++i) b.add(0.0, 0.0, 0.35, 0.35, 0.0);
  const auto s = b.measure();
  EXPECT_EQ(s.pairs_over_1pct, n * (n - 1) / 2);
  EXPECT_EQ(s.max_pen_over_radius, 2.0);
  EXPECT_EQ(s.pair_tests, 0u);
}

TEST(SceneResidual, CoincidentGroupAgainstNeighbour) {
  // Two bodies at the origin, one 0.5 away (r 0.5): 1 coincident pair (pen 2) + 2 pairs of pen 1.
  Bodies b;
  b.add(0.0, 0.0, 0.0, 0.5, 0.0);
  b.add(0.0, 0.0, 0.0, 0.5, 0.0);
  b.add(0.5, 0.0, 0.0, 0.5, 0.0);
  const auto s = b.measure();
  EXPECT_EQ(s.pairs_over_1pct, 3u);
  EXPECT_EQ(s.max_pen_over_radius, 2.0);
}

TEST(SceneResidual, OnePercentThresholdIsStrict) {
  // r = 1: pen over radius 0.015 counts, 0.005 does not.
  Bodies b;
  b.add(0.0, 0.0, 0.0, 1.0, 0.0);
  b.add(1.985, 0.0, 0.0, 1.0, 0.0);
  b.add(10.0, 0.0, 0.0, 1.0, 0.0);
  b.add(11.995, 0.0, 0.0, 1.0, 0.0);
  EXPECT_EQ(b.measure().pairs_over_1pct, 1u);
}

TEST(SceneResidual, P99IsNearestRankOverBodies) {
  // 200 bodies: one overlapping pair (2 bodies with pen 0.5), 198 apart. Rank ceil(0.99 * 200) =
  // 198 of the ascending list is still 0; with 4 overlapping bodies (2 pairs) rank 198 is 0.5.
  Bodies b;
  for (int i = 0; i < 198; ++i) b.add(10.0 * i, 100.0, 0.0, 0.5, 0.0);
  b.add(0.0, 0.0, 0.0, 0.5, 0.0);
  b.add(0.75, 0.0, 0.0, 0.5, 0.0);
  EXPECT_EQ(b.measure().p99_pen_over_radius, 0.0);
  b.x[0] = 5.0, b.y[0] = 0.0;  // move two far bodies into another overlapping pair
  b.x[1] = 5.75, b.y[1] = 0.0;
  EXPECT_EQ(b.measure().p99_pen_over_radius, 0.5);
}

TEST(SceneResidual, NanBodiesAreCountedAndIgnored) {
  Bodies b;
  b.add(0.0, 0.0, 0.0, 0.5, 0.0);
  b.add(std::nan(""), 0.0, 0.0, 0.5, 0.0);
  b.add(0.0, std::numeric_limits<double>::infinity(), 0.0, 0.5, 0.0);
  const auto s = b.measure();
  EXPECT_EQ(s.nan_count, 2u);
  EXPECT_EQ(s.bodies, 1u);
  EXPECT_EQ(s.max_pen_over_radius, 0.0);
}

TEST(SceneResidual, NeighbourCellsAreSearchedInEveryDirection) {
  // Largest radius 1 -> cell edge 2. For each of the 8 neighbour directions, one pair straddles the
  // boundary of the cell around (40k, 0) (k-th pair far from the others); each must be found.
  Bodies b;
  b.add(-100.0, -100.0, 0.0, 1.0, 0.0);  // sets the cell size
  const int dirs[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, 1}, {1, -1}, {-1, -1}};
  for (int k = 0; k < 8; ++k) {
    const double cx = 40.0 * k + 1.0, cy = 1.0;  // centre of cell (20k, 0)
    b.add(cx + 0.9 * dirs[k][0], cy + 0.9 * dirs[k][1], 0.0, 0.25, 0.0);
    b.add(cx + 1.1 * dirs[k][0], cy + 1.1 * dirs[k][1], 0.0, 0.25, 0.0);
  }
  const auto s = b.measure();
  EXPECT_EQ(s.pairs_over_1pct, 8u);
}

}  // namespace
}  // namespace throng::scene
