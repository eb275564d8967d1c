// StaticScenery::first_hit_fraction (fast movers must not tunnel) and ground_height.
#include <gtest/gtest.h>

#include <cmath>

#include "throng/geometry/static_scenery.h"

namespace throng::geom {
namespace {

constexpr double kR = 0.35;

Capsule upright(double x, double y, double z_lo, double z_hi, double r) {
  return {{x, y, z_lo}, {x, y, z_hi}, r};
}

Capsule moved(const Capsule& c, const Vec3& d, double f) {
  return {c.p0 + d * f, c.p1 + d * f, c.radius};
}

std::size_t contacts(const StaticScenery& s, const Capsule& c) {
  std::vector<SceneryContact> out;
  s.query(c, out);
  return out.size();
}

// A 5 cm wall whose near face is at x = 1: x in [1, 1.05].
StaticScenery thin_wall_scene() {
  StaticScenery s;
  s.add_box({1.025, 0, 1.5}, {0.025, 2, 1.5}, 0.0);
  s.build();
  return s;
}

// Found by fuzzing (tests/fuzz world_checkpoint): a displacement of 1e33 m made the sample count's
// double-to-long conversion overflow (undefined behavior; the sanitizer build checks it). The count
// is capped at kMaxSamples instead (so such a move may step over a wall: World refuses desired
// speeds above 1000 m/s, in set_desired_velocity and in checkpoints, long before that).
TEST(GeomSceneryMotion, AbsurdDisplacementIsCappedNotOverflowed) {
  const StaticScenery s = thin_wall_scene();
  const Capsule mover = upright(0, 0, 0.5, 1.5, kR);
  for (const double x : {1e33, -1e300, 1e18}) {
    const double f = s.first_hit_fraction(mover, Vec3{x, 0, 0});
    EXPECT_GE(f, 0.0) << x;
    EXPECT_LE(f, 1.0) << x;
  }
}

TEST(GeomSceneryMotion, FastMoverStopsInFrontOfThinWall) {
  const StaticScenery s = thin_wall_scene();
  const Capsule mover = upright(0, 0, 0.5, 1.5, kR);
  const Vec3 d{2, 0, 0};
  const double f = s.first_hit_fraction(mover, d);
  // The capsule touches when its axis reaches x = 1 - r.
  EXPECT_NEAR(f, (1.0 - kR) / 2.0, 1e-9);
  const Capsule end = moved(mover, d, f);
  EXPECT_LE(end.p0.x + kR, 1.0 + 1e-9);  // in front of the wall, never past it
  EXPECT_EQ(contacts(s, end), 0u);
  EXPECT_GT(contacts(s, moved(mover, d, f + 1e-6)), 0u);  // and really at the wall
}

TEST(GeomSceneryMotion, TiltedMoverAndMeshWallStillStop) {
  StaticScenery s;
  // The same 5 cm wall as a 12-triangle mesh, at y in [8, 12], clear of the box (|y| <= 2).
  const Vec3 lo{1.0, 8, 0};
  const Vec3 hi{1.05, 12, 3};
  std::vector<Vec3> v{{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z},
                      {lo.x, hi.y, lo.z}, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z},
                      {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  s.add_mesh(v, {{0, 2, 1},
                 {0, 3, 2},
                 {4, 5, 6},
                 {4, 6, 7},
                 {0, 1, 5},
                 {0, 5, 4},
                 {1, 2, 6},
                 {1, 6, 5},
                 {2, 3, 7},
                 {2, 7, 6},
                 {3, 0, 4},
                 {3, 4, 7}});
  s.add_box({1.025, 0, 1.5}, {0.025, 2, 1.5}, 0.0);
  s.build();
  const Vec3 d{2, 0, 0};

  // Upright mover against the mesh.
  const Capsule m = upright(0, 10, 0.5, 1.5, kR);
  EXPECT_NEAR(s.first_hit_fraction(m, d), (1.0 - kR) / 2.0, 1e-9);

  // Mover tilted 0.3 rad towards the wall: its upper end leads by 0.5 sin(0.3).
  const double a = 0.3;
  const Vec3 half{0.5 * std::sin(a), 0, 0.5 * std::cos(a)};
  for (const double y : {0.0, 10.0}) {
    const Vec3 c{0, y, 1.0};
    const Capsule t{c - half, c + half, kR};
    const double f = s.first_hit_fraction(t, d);
    EXPECT_NEAR(f, (1.0 - kR - half.x) / 2.0, 1e-7) << "y=" << y;
    EXPECT_EQ(contacts(s, moved(t, d, f)), 0u);
    EXPECT_LE(c.x + d.x * f + half.x + kR, 1.0 + 1e-7);
  }
}

TEST(GeomSceneryMotion, RotatedWallAndDiagonalApproach) {
  StaticScenery s;
  const double yaw = 0.7;
  const Vec3 u{std::cos(yaw), std::sin(yaw), 0};
  const Vec3 c{3, 1, 1.5};
  s.add_box(c, {0.025, 3, 1.5}, yaw);  // thin wall, normal u
  s.build();
  // Start 2 m in front of the wall's near face and move 4 m straight at it (+u).
  const Vec3 start = c - u * (0.025 + 2.0);
  const Capsule m = upright(start.x, start.y, 0.5, 1.5, kR);
  const Vec3 d = u * 4.0;
  EXPECT_NEAR(s.first_hit_fraction(m, d), (2.0 - kR) / 4.0, 1e-9);
  // Diagonal: 45 degrees to the wall normal; it must travel (2 - r) along u.
  const Vec3 v{-std::sin(yaw), std::cos(yaw), 0};
  const Vec3 diag = (u + v) * 3.0;
  EXPECT_NEAR(s.first_hit_fraction(m, diag), (2.0 - kR) / 3.0, 1e-9);
}

TEST(GeomSceneryMotion, MissesAndStartingContacts) {
  const StaticScenery s = thin_wall_scene();
  // Passing beside the wall's end (y in [-2, 2]) with clearance.
  EXPECT_EQ(s.first_hit_fraction(upright(0, 2.5, 0.5, 1.5, kR), {2, 0, 0}), 1.0);
  // Jumping over it: the wall top is z = 3.
  EXPECT_EQ(s.first_hit_fraction(upright(0, 0, 3.5, 4.5, kR), {2, 0, 0}), 1.0);
  EXPECT_EQ(s.first_hit_fraction(upright(0, 0, 0.5, 1.5, kR), {0, 0, 0}), 1.0);
  // Resting 1 cm inside the wall: sliding along it or backing away is free, going deeper is not.
  const Capsule resting = upright(1.0 - kR + 0.01, 0, 0.5, 1.5, kR);
  EXPECT_EQ(contacts(s, resting), 1u);
  EXPECT_EQ(s.first_hit_fraction(resting, {0, 1, 0}), 1.0);
  EXPECT_EQ(s.first_hit_fraction(resting, {-1, 0, 0}), 1.0);
  EXPECT_LT(s.first_hit_fraction(resting, {0.5, 0, 0}), 1e-8);
}

TEST(GeomSceneryMotion, SweepMatchesFineBruteForce) {
  // Random fast moves through a cluttered scene: the returned pose is contact-free (or no deeper
  // than at the start), and a brute-force scan finds no earlier first contact.
  StaticScenery s;
  s.add_box({2, 0, 1}, {0.05, 1.5, 1}, 0.3);
  s.add_box({-1, 2, 0.5}, {1, 0.05, 0.5}, -0.2);
  s.add_cylinder({0.5, -2, 1}, 0.1, 1.0);
  s.add_cylinder({-2, -1, 1}, 0.4, 1.0);
  s.build();
  std::uint64_t state = 12345;
  auto next = [&state] {  // small LCG: deterministic, independent of <random>'s distributions
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  int hits = 0;
  for (int i = 0; i < 200; ++i) {
    const double x = -0.5 + next();  // one draw per statement: argument order is unspecified
    const double y = -0.5 + next();
    const Capsule m = upright(x, y, 0.4, 1.2, 0.2 + 0.2 * next());
    if (contacts(s, m) != 0) continue;
    const double phi = 6.283185307179586 * next();
    const Vec3 d = Vec3{std::cos(phi), std::sin(phi), 0} * (1.0 + 3.0 * next());
    const double f = s.first_hit_fraction(m, d);
    ASSERT_EQ(contacts(s, moved(m, d, f)), 0u) << i;
    for (int k = 0; k < 400; ++k) {  // 1 cm steps for a 4 m move
      const double g = f * k / 400.0;
      ASSERT_EQ(contacts(s, moved(m, d, g)), 0u) << i << " at " << g;
    }
    if (f < 1.0) {
      ++hits;
      ASSERT_GT(contacts(s, moved(m, d, std::min(1.0, f + 1e-6))), 0u) << i;
    }
  }
  EXPECT_GT(hits, 20);
}

TEST(GeomSceneryMotion, GroundHeightOnLedge) {
  StaticScenery s;
  s.add_box({0, 0, 0.5}, {1, 1, 0.5}, 0.0);        // ledge, top z = 1
  s.add_box({0.5, 0, 1.1}, {0.2, 0.2, 0.1}, 0.0);  // small step on it, top z = 1.2
  s.add_box({5, 0, 3.0}, {1, 1, 0.1}, 0.4);        // a platform overhead, top z = 3.1
  s.build();
  EXPECT_EQ(s.ground_height(0, 0, 1.0), 1.0);   // standing on the ledge
  EXPECT_EQ(s.ground_height(0, 0, 0.75), 1.0);  // 0.25 below its top: within the step tolerance
  EXPECT_EQ(s.ground_height(0, 0, 0.65), 0.0);  // 0.35 below: the ledge is a wall, ground is 0
  EXPECT_DOUBLE_EQ(s.ground_height(0.5, 0, 1.0), 1.1 + 0.1);  // the step's top wins when reachable
  EXPECT_EQ(s.ground_height(0.5, 0, 0.85), 1.0);              // 1.2 > 0.85 + 0.3: only the ledge
  EXPECT_EQ(s.ground_height(1.5, 0, 1.0), 0.0);               // off the ledge
  EXPECT_EQ(s.ground_height(1.0, 0, 1.0), 1.0);               // on its edge (inclusive)
  EXPECT_EQ(s.ground_height(5, 0, 0.0), 0.0);                 // under the platform
  EXPECT_DOUBLE_EQ(s.ground_height(5, 0, 3.2), 3.0 + 0.1);    // on it
  // Rotated footprint: just inside / just outside the platform's rotated corner.
  const double yaw = 0.4;
  const Vec3 corner_dir{std::cos(yaw) - std::sin(yaw), std::sin(yaw) + std::cos(yaw), 0};
  const Vec3 inside = Vec3{5, 0, 0} + corner_dir * 0.99;   // just inside the rotated corner
  const Vec3 outside = Vec3{5, 0, 0} + corner_dir * 1.01;  // just outside it
  EXPECT_DOUBLE_EQ(s.ground_height(inside.x, inside.y, 3.1), 3.0 + 0.1);
  EXPECT_EQ(s.ground_height(outside.x, outside.y, 3.1), 0.0);
  // Feet far below ground with nothing under them: 0.
  EXPECT_EQ(s.ground_height(0, 0, -5.0), 0.0);
}

TEST(GeomSceneryMotion, GroundHeightOnCylinderAndMeshRamp) {
  StaticScenery s;
  s.add_cylinder({0, 0, 0.25}, 0.5, 0.25);  // top z = 0.5
  // A ramp rising from z = 0 at x = 2 to z = 1 at x = 4, y in [-1, 1].
  s.add_mesh({{2, -1, 0}, {4, -1, 1}, {4, 1, 1}, {2, 1, 0}}, {{0, 1, 2}, {0, 2, 3}});
  s.build();
  EXPECT_EQ(s.ground_height(0.3, 0.3, 0.5), 0.5);
  EXPECT_EQ(s.ground_height(0.4, 0.4, 0.5), 0.0);  // outside the disc (radius 0.566 > 0.5)
  EXPECT_NEAR(s.ground_height(3.0, 0.2, 0.5), 0.5, 1e-15);
  EXPECT_NEAR(s.ground_height(3.5, -0.7, 0.75), 0.75, 1e-15);
  EXPECT_NEAR(s.ground_height(3.9, 0.0, 0.7), 0.95, 1e-15);  // 0.25 above the feet: a step
  EXPECT_EQ(s.ground_height(3.9, 0.0, 0.6), 0.0);            // too high a step
}

}  // namespace
}  // namespace throng::geom
