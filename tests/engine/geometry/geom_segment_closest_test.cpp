// Segment-segment closest points on hand-built cases whose answers follow from the geometry.
#include <gtest/gtest.h>

#include "geometry/geom_test_util.h"

#include "throng/geometry/segment_closest.h"

namespace throng::geom {
namespace {

TEST(GeomSegmentClosest, PerpendicularSkewSegmentsMeetAtTheirMiddles) {
  const auto r = closest_points_segment_segment({-1, 0, 0}, {1, 0, 0}, {0, -1, 2}, {0, 1, 2});
  EXPECT_DOUBLE_EQ(r.s, 0.5);
  EXPECT_DOUBLE_EQ(r.t, 0.5);
  EXPECT_DOUBLE_EQ(r.distance_squared, 4.0);
  expect_vec(r.point_1, {0, 0, 0}, 0.0);
  expect_vec(r.point_2, {0, 0, 2}, 0.0);
  expect_vec(r.delta, {0, 0, 2}, 0.0);
}

TEST(GeomSegmentClosest, EndpointAgainstInterior) {
  const auto r = closest_points_segment_segment({0, 0, 0}, {1, 0, 0}, {2, -1, 0}, {2, 1, 0});
  EXPECT_DOUBLE_EQ(r.s, 1.0);
  EXPECT_DOUBLE_EQ(r.t, 0.5);
  EXPECT_DOUBLE_EQ(r.distance_squared, 1.0);
}

TEST(GeomSegmentClosest, ParallelOverlapGivesMiddleOfOverlap) {
  // q projects onto s in [0.5, 1.5]; the overlap with [0, 1] is [0.5, 1], middle 0.75.
  const auto r = closest_points_segment_segment({0, 0, 0}, {2, 0, 0}, {1, 1, 0}, {3, 1, 0});
  EXPECT_DOUBLE_EQ(r.distance_squared, 1.0);
  EXPECT_DOUBLE_EQ(r.s, 0.75);
  EXPECT_DOUBLE_EQ(r.t, 0.25);
  // Anti-parallel: same overlap, same answer for the points.
  const auto q = closest_points_segment_segment({0, 0, 0}, {2, 0, 0}, {3, 1, 0}, {1, 1, 0});
  EXPECT_DOUBLE_EQ(q.distance_squared, 1.0);
  expect_vec(q.point_1, r.point_1, 1e-15);
  expect_vec(q.point_2, r.point_2, 1e-15);
}

TEST(GeomSegmentClosest, ParallelDisjointGivesFacingEnds) {
  const auto r = closest_points_segment_segment({0, 0, 0}, {1, 0, 0}, {3, 1, 0}, {4, 1, 0});
  EXPECT_DOUBLE_EQ(r.s, 1.0);
  EXPECT_DOUBLE_EQ(r.t, 0.0);
  EXPECT_DOUBLE_EQ(r.distance_squared, 5.0);
  const auto l = closest_points_segment_segment({0, 0, 0}, {1, 0, 0}, {-4, 1, 0}, {-3, 1, 0});
  EXPECT_DOUBLE_EQ(l.s, 0.0);
  EXPECT_DOUBLE_EQ(l.t, 1.0);
  EXPECT_DOUBLE_EQ(l.distance_squared, 10.0);
}

TEST(GeomSegmentClosest, ZeroLengthSegments) {
  const auto pp = closest_points_segment_segment({1, 2, 3}, {1, 2, 3}, {1, 2, 5}, {1, 2, 5});
  EXPECT_DOUBLE_EQ(pp.distance_squared, 4.0);
  const auto ps = closest_points_segment_segment({0.5, 1, 0}, {0.5, 1, 0}, {0, 0, 0}, {1, 0, 0});
  EXPECT_DOUBLE_EQ(ps.t, 0.5);
  EXPECT_DOUBLE_EQ(ps.distance_squared, 1.0);
  const auto sp = closest_points_segment_segment({0, 0, 0}, {1, 0, 0}, {2, 1, 0}, {2, 1, 0});
  EXPECT_DOUBLE_EQ(sp.s, 1.0);
  EXPECT_DOUBLE_EQ(sp.distance_squared, 2.0);
}

TEST(GeomSegmentClosest, NearlyParallelAxesStayExact) {
  // q climbs 2e-10 in y over x in [0, 1], crossing the x axis exactly at x = 0.5, and sits 1e-3
  // above it in z: the exact distance is 1e-3. A plain (ae - b^2) solve loses ~7 digits here.
  const auto r =
      closest_points_segment_segment({0, 0, 0}, {1, 0, 0}, {0, -1e-10, 1e-3}, {1, 1e-10, 1e-3});
  EXPECT_NEAR(std::sqrt(r.distance_squared), 1e-3, 1e-18);
  EXPECT_NEAR(r.s, 0.5, 1e-6);
  // In the plane z = 0 they cross: distance 0 (to rounding).
  const auto c =
      closest_points_segment_segment({0, 0, 0}, {1, 0, 0}, {0, -1e-10, 0}, {1, 1e-10, 0});
  EXPECT_LE(std::sqrt(c.distance_squared), 1e-16);
}

TEST(GeomSegmentClosest, FarFromOriginKeepsLocalPrecision) {
  const Vec3 o{1e4, -7e3, 12.0};
  const auto r = closest_points_segment_segment(o + Vec3{-1, 0, 0}, o + Vec3{1, 0, 0},
                                                o + Vec3{0, -1, 0.25}, o + Vec3{0, 1, 0.25});
  EXPECT_EQ(r.delta, (Vec3{0, 0, 0.25}));  // computed relative to p0: exact
  EXPECT_DOUBLE_EQ(r.distance_squared, 0.0625);
}

}  // namespace
}  // namespace throng::geom
