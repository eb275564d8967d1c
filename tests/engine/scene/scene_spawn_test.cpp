// Spawn placement: inside the shape, deterministic, uniform in area.
#include <gtest/gtest.h>

#include <cmath>

#include "throng/scene/spawn.h"

namespace throng::scene {
namespace {

TEST(SceneSpawn, Uniform01IsInUnitIntervalAndDeterministic) {
  std::mt19937_64 a(42), b(42);
  for (int i = 0; i < 1000; ++i) {
    const double u = uniform01(a);
    EXPECT_GE(u, 0.0);
    EXPECT_LT(u, 1.0);
    EXPECT_EQ(u, uniform01(b));
  }
}

TEST(SceneSpawn, DiskIsInsideAndUniformInArea) {
  SpawnShape d;
  d.kind = SpawnAreaKind::disk;
  d.centre = {5.0, -3.0};
  d.radius_m = 10.0;
  const auto pts = spawn_positions(d, 20'000, 7);
  ASSERT_EQ(pts.size(), 20'000u);
  int inner = 0;  // inside radius R / sqrt(2): half the area, so about half the bodies
  for (const auto& p : pts) {
    const double r = std::hypot(p.x - 5.0, p.y + 3.0);
    EXPECT_LE(r, 10.0);
    if (r < 10.0 / std::sqrt(2.0)) ++inner;
  }
  EXPECT_NEAR(inner / 20'000.0, 0.5, 0.02);
  EXPECT_EQ(spawn_positions(d, 20'000, 7), pts);
  EXPECT_NE(spawn_positions(d, 20'000, 8), pts);
}

TEST(SceneSpawn, RectRotatesWithYaw) {
  SpawnShape r;
  r.kind = SpawnAreaKind::rect;
  r.centre = {0.0, 0.0};
  r.half_extents_m = {10.0, 1.0};
  r.yaw_deg = 90.0;  // long side along y
  for (const auto& p : spawn_positions(r, 500, 1)) {
    EXPECT_LE(std::abs(p.x), 1.0 + 1e-9);
    EXPECT_LE(std::abs(p.y), 10.0 + 1e-9);
  }
}

TEST(SceneSpawn, PointAndLine) {
  SpawnShape pt;
  pt.kind = SpawnAreaKind::point;
  pt.centre = {2.0, 3.0};
  for (const auto& p : spawn_positions(pt, 5, 1)) EXPECT_EQ(p, (Vec2{2.0, 3.0}));
  SpawnShape l;
  l.kind = SpawnAreaKind::line;
  l.from = {0.0, 0.0};
  l.to = {4.0, 0.0};
  const auto pts = spawn_positions(l, 4, 1);  // segment midpoints
  ASSERT_EQ(pts.size(), 4u);
  EXPECT_EQ(pts[0].x, 0.5);
  EXPECT_EQ(pts[3].x, 3.5);
}

TEST(SceneSpawn, GroupStreamsAreIndependent) {
  EXPECT_NE(group_seed(1, 0), group_seed(1, 1));
  EXPECT_NE(group_seed(1, 0), group_seed(2, 0));
  EXPECT_EQ(group_seed(9, 3), group_seed(9, 3));
}

}  // namespace
}  // namespace throng::scene
