// Hard cases for the solver. Each ends with no NaN, bounded cost (candidate pairs and iterations
// never exceed their caps) and bounded residual penetration, checked by brute force here rather
// than by the solver's own figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <random>
#include <vector>

#include "world/world_fixtures.h"

namespace throng {
namespace {

using namespace throng::test;

struct Residual {
  double max_pen_over_radius = 0.0;
  std::size_t nan_count = 0;
};

// O(N^2) reference: fine for the few thousand bodies these tests use.
Residual brute_force_residual(const World& w) {
  Residual res;
  const auto x = w.pos_x(), y = w.pos_y(), z = w.pos_z(), r = w.radius(), hh = w.half_height();
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || !std::isfinite(z[i])) ++res.nan_count;
    for (std::size_t j = i + 1; j < x.size(); ++j) {
      const double gap = std::max(0.0, std::fabs(z[j] - z[i]) - hh[i] - hh[j]);
      const double d = std::sqrt((x[j] - x[i]) * (x[j] - x[i]) + (y[j] - y[i]) * (y[j] - y[i]) + gap * gap);
      const double pen = std::max(0.0, r[i] + r[j] - d) / std::min(r[i], r[j]);
      res.max_pen_over_radius = std::max(res.max_pen_over_radius, pen);
    }
  }
  return res;
}

WorldSettings budget(std::uint32_t iterations) {
  WorldSettings s;
  s.iterations = iterations;
  return s;
}

TEST(WorldHardCases, TenThousandAgentsStartedAtOnePoint) {
  WorldSettings s = budget(8);
  s.record_push_events = false;
  World w(s, test_table(), weight_policy(params::PushMode::ratio, 100.0));
  for (int i = 0; i < 10000; ++i) add_sphere(w, 0.0, 0.0);
  // The first tick recognises the pile (one cell, thousands of times its capacity) and lays it
  // out; from then on it is an ordinary packed crowd.
  const StepStats& first = w.step();
  EXPECT_EQ(first.pile_relief_bodies, 10000u);
  EXPECT_LE(first.candidate_pairs, 10000u * s.max_candidates_per_body);
  std::uint32_t max_pairs = 0;
  for (int t = 0; t < 30; ++t) {
    const StepStats& st = w.step();
    EXPECT_EQ(st.pile_relief_bodies, 0u);
    ASSERT_LE(st.iterations_used, s.iterations + s.extra_iterations);
    max_pairs = std::max(max_pairs, st.candidate_pairs);
  }
  // Linear cost: a packed crowd has about three candidate pairs per body (half of six neighbours).
  EXPECT_LE(max_pairs, 4u * 10000u);
  const Residual res = brute_force_residual(w);
  EXPECT_EQ(res.nan_count, 0u);
  EXPECT_LT(res.max_pen_over_radius, 0.05);
  // Compact: about the radius of a hexagonally packed disk of 10,000 bodies (37 m), not scattered.
  double max_r = 0.0;
  for (std::size_t i = 0; i < w.body_count(); ++i) max_r = std::max(max_r, std::hypot(w.pos_x()[i], w.pos_y()[i]));
  EXPECT_GT(max_r, 30.0);
  EXPECT_LT(max_r, 50.0);
}

TEST(WorldHardCases, CrowdSqueezedBetweenTwoWalls) {
  World w(budget(16), test_table(), weight_policy(params::PushMode::ratio, 100.0));
  w.add_fixed_box({0.0, -2.0, 1.0}, {30.0, 0.25, 1.0}, 0.0);  // walls at y = -1.75 and y = +1.75
  w.add_fixed_box({0.0, 2.0, 1.0}, {30.0, 0.25, 1.0}, 0.0);
  std::vector<ObjectId> ids;
  for (int i = 0; i < 200; ++i) ids.push_back(add_sphere(w, -10.0 + 0.1 * i, -1.4 + 0.014 * (i % 200)));
  for (int t = 0; t < 300; ++t) {
    for (std::size_t i = 0; i < ids.size(); ++i) w.set_desired_velocity(ids[i], {i % 2 ? 1.0 : -1.0, (i % 3) - 1.0, 0.0});
    w.step();
  }
  double static_pen = 0.0;
  for (std::size_t i = 0; i < w.body_count(); ++i) static_pen = std::max(static_pen, w.scenery_max_penetration(i));
  EXPECT_LE(static_pen, 1e-6);  // walls always win
  for (std::size_t i = 0; i < w.body_count(); ++i) {
    EXPECT_GE(w.pos_y()[i], -1.75 + 0.35 - 1e-6);
    EXPECT_LE(w.pos_y()[i], 1.75 - 0.35 + 1e-6);
  }
  const Residual res = brute_force_residual(w);
  EXPECT_EQ(res.nan_count, 0u);
  EXPECT_LT(res.max_pen_over_radius, 0.25);
}

// Which bodies are near scenery is a bitmap over the scenery cells' bounding box, or a search of
// the cells when that box holds more than 4 Mi cells (2 m). Both must stop the bodies at every
// wall: here two walls 9 km apart on a diagonal (the search), then 90 m apart (the bitmap), and
// bodies pressing into each wall from both sides, some in the bitmap's edge cells.
TEST(WorldHardCases, WallsFarApartStopBodiesAsWallsCloseTogether) {
  for (const double gap : {9000.0, 90.0}) {
    SCOPED_TRACE(gap);
    World w(budget(8), test_table(), weight_policy(params::PushMode::ratio, 100.0));
    std::vector<ObjectId> ids;
    std::vector<double> wall_x;
    for (const double cx : {-0.5 * gap, 0.5 * gap}) {
      const double cy = cx;
      w.add_fixed_box({cx, cy, 1.0}, {0.25, 3.0, 1.0}, 0.0);  // faces at cx -+ 0.25
      wall_x.push_back(cx);
      for (int k = 0; k < 6; ++k) {
        ids.push_back(add_sphere(w, cx - 1.5, cy - 2.5 + k, 0.35));  // left of the wall, walking right
        ids.push_back(add_sphere(w, cx + 1.5, cy - 2.5 + k, 0.35));  // right of it, walking left
      }
    }
    for (int t = 0; t < 90; ++t) {
      for (std::size_t i = 0; i < ids.size(); ++i) w.set_desired_velocity(ids[i], {i % 2 == 0 ? 1.5 : -1.5, 0.0, 0.0});
      w.step();
    }
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const double cx = wall_x[i / 12];
      const double x = w.position(ids[i]).x;
      if (i % 2 == 0) {
        EXPECT_NEAR(x, cx - 0.25 - 0.35, 1e-6) << i;  // stopped at the wall's left face
      } else {
        EXPECT_NEAR(x, cx + 0.25 + 0.35, 1e-6) << i;
      }
    }
  }
}

// Mirrored (side = -1: the wall on the right): in the solver's order the pinned body is then the
// pair's second body instead of its first, so both branches of pinned_share are exercised.
TEST(WorldHardCases, AgentPinnedBetweenWallAndHeavyPusher) {
  for (const double side : {1.0, -1.0}) {
    World w(budget(8), test_table(), weight_policy(params::PushMode::ratio, 10.0));  // 200 vs 80 kg: share 1 - 6e-6
    w.add_fixed_box({-1.0 * side, 0.0, 1.0}, {1.0, 5.0, 1.0}, 0.0);  // wall face at x = 0
    const ObjectId pinned = add_sphere(w, 0.35 * side, 0.0, 0.35, "infantry");
    const ObjectId heavy = add_sphere(w, 1.0 * side, 0.0, 0.35, "heavy");
    for (int t = 0; t < 120; ++t) {
      w.set_desired_velocity(heavy, {-1.5 * side, 0.0, 0.0});
      w.step();
      ASSERT_GE(side * w.position(pinned).x, 0.35 - 1e-9) << "side " << side << " tick " << t;  // never in the wall
    }
    // The heavy pusher is stopped by the pinned body, which the wall backs up.
    EXPECT_NEAR(side * (w.position(heavy).x - w.position(pinned).x), 0.7, 1e-6) << "side " << side;
  }
}

// A body resting on a wall, pushed at 45 degrees by a body of the same weight, takes its half of the
// push (pinned_share: at most the smaller share): the wall's plane takes back what went into the
// wall and the rest slides it along the wall. Had it taken nothing (the earlier rule), it would
// stay where it is and a pocket between pillars that holds one body too many could never open.
// Both sides of the wall, as above. With one weight the pinned body's share is exactly a half.
TEST(WorldHardCases, BodyOnAWallGivesWayAlongItToAnEqualPusher) {
  for (const double side : {1.0, -1.0}) {
    World w(budget(8), test_table(), weight_policy(params::PushMode::ratio, 10.0));
    w.add_fixed_box({-1.0 * side, 0.0, 1.0}, {1.0, 5.0, 1.0}, 0.0);  // wall face at x = 0
    const double c = std::sqrt(0.5);
    const ObjectId resting = add_sphere(w, 0.35 * side, 0.0, 0.35, "infantry");
    const ObjectId pusher = add_sphere(w, (0.35 + 0.5 * c) * side, 0.5 * c, 0.35, "infantry");  // 0.2 m deep
    w.step();
    const Vec3 a = w.position(resting), b = w.position(pusher);
    EXPECT_GE(side * a.x, 0.35 - 1e-9) << "side " << side;  // not in the wall
    EXPECT_LT(a.y, -0.03) << "side " << side;               // slid along it, away from the pusher
    EXPECT_GT(distance_xy(a, b), 0.7 - 1e-3) << "side " << side;  // and the pair is apart
  }
}

// A light body caught between two heavy ones that both overlap it: with exact shares (~1 for the
// light body) every push only moves the light body, so Gauss-Seidel flips it from one heavy body to
// the other and never converges. The conflict share limit lets later pushes of a pair move the
// heavy bodies too.
TEST(WorldHardCases, LightBodySqueezedBetweenHeavyOnesIsResolved) {
  auto residual_after = [](double conflict_limit, int ticks) {
    WorldSettings s = budget(8);
    s.conflict_share_limit = conflict_limit;
    World w(s, test_table(), weight_policy(params::PushMode::ratio, 10.0));  // 200 vs 50 kg: share 1 - 3e-7
    add_sphere(w, 0.0, 0.0, 0.35, "heavy");
    add_sphere(w, 0.6, 0.0, 0.35, "light");
    add_sphere(w, 1.2, 0.0, 0.35, "heavy");
    for (int t = 0; t < ticks; ++t) w.step();
    return brute_force_residual(w).max_pen_over_radius;
  };
  std::printf("squeezed: exact %g / %g, limited %g / %g (1 / 10 ticks)\n", residual_after(0.0, 1),
              residual_after(0.0, 10), residual_after(0.25, 1), residual_after(0.25, 10));
  // Exact shares: the overlap only moves from one side to the other, tick after tick.
  EXPECT_GT(residual_after(0.0, 10), 0.1);
  // Limited: the heavy bodies give way; most of it goes in the first tick, all of it in a few.
  EXPECT_LT(residual_after(0.25, 1), 0.5 * residual_after(0.0, 1));
  EXPECT_LT(residual_after(0.25, 10), 1e-3);
}

// A pair that starts its tick held together by its neighbours takes the conflict share from the
// start (held_by_neighbours in pair_schedule.h). A light body walking into a heavy one, tick after
// tick, also carries a push from tick to tick, but no more than its own step closes: it must keep
// the patent's exact ratio, the heavy body giving way as far as with the limit off.
TEST(WorldHardCases, LightBodyWalkingIntoAHeavyOneKeepsTheExactRatio) {
  // `rows` walkers side by side, 4 m apart, each into its own heavy body: one pair is solved in the
  // pairs' own order in double precision; 300 are scheduled (kMinScheduledPairs) and take the fast
  // pairs' float kernel, its 8 r warm-start cap and the vectorised held test.
  struct Travel {
    double mean = 0.0;
    std::vector<double> each;
    std::uint32_t band_sweeps = 0;  // of the last tick: > 0 only in a scheduled solve
  };
  auto heavy_travel = [](double conflict_limit, double carry, int rows) {
    WorldSettings s = budget(8);
    s.conflict_share_limit = conflict_limit;
    s.blocked_motion_carry = carry;
    World w(s, test_table(), weight_policy(params::PushMode::ratio, 100.0));
    std::vector<ObjectId> light, heavy;
    for (int k = 0; k < rows; ++k) {
      light.push_back(add_sphere(w, 0.0, 4.0 * k, 0.35, "light"));
      heavy.push_back(add_sphere(w, 0.75, 4.0 * k, 0.35, "heavy"));
    }
    Travel t;
    for (int tick = 0; tick < 540; ++tick) {
      for (const ObjectId id : light) w.set_desired_velocity(id, {1.5, 0.0, 0.0});
      t.band_sweeps = w.step().band_sweeps;
    }
    for (int k = 0; k < rows; ++k) {
      EXPECT_NEAR(w.position(heavy[k]).x - w.position(light[k]).x, 0.7, 1e-3);
      t.each.push_back(w.position(heavy[k]).x - 0.75);
      t.mean += t.each.back() / rows;
    }
    return t;
  };
  for (const int rows : {1, 300}) {
    for (const double carry : {0.0, 0.9}) {
      const Travel exact = heavy_travel(0.0, carry, rows), limited = heavy_travel(0.35, carry, rows);
      std::printf("%d rows, carry %.1f: heavy bodies moved %.4f m with exact shares, %.4f m with the limit\n", rows,
                  carry, exact.mean, limited.mean);
      EXPECT_EQ(limited.band_sweeps > 0, rows == 300) << "the solve path this case is about";
      EXPECT_GT(exact.mean, 1.0);  // the light body does push it, by its small share
      // The same travel, but for a few ticks at first contact with the blocked-motion carry, when
      // the walker it slows carries a little more than it closes (about 0.009 m here; at the conflict
      // share throughout, the heavy body would go nearly twice as far).
      for (int k = 0; k < rows; ++k) ASSERT_NEAR(limited.each[k], exact.each[k], 0.015) << rows << " rows, row " << k;
    }
  }
}

TEST(WorldHardCases, HugePenetrationDeeperThanARadius) {
  World w(budget(8), test_table(), weight_policy(params::PushMode::ratio, 100.0));
  const ObjectId a = add_sphere(w, 0.0, 0.0, 1.0);
  const ObjectId b = add_sphere(w, 0.05, 0.0, 1.0);  // 1.95 deep
  w.step();
  EXPECT_NEAR(distance_xy(w.position(a), w.position(b)), 2.0, 1e-9);
  EXPECT_LT(w.position(a).x, 0.0);  // pushed apart along the original line, not flipped
  EXPECT_GT(w.position(b).x, 0.05);
}

TEST(WorldHardCases, TinyAndHugeRadiiInOneScene) {
  World w(budget(16), test_table(), weight_policy(params::PushMode::ratio, 100.0));
  add_sphere(w, 0.0, 0.0, 10.0);
  for (int i = 0; i < 50; ++i) add_sphere(w, 9.0 + 0.0005 * i, 0.001 * i, 1e-3);
  for (int i = 0; i < 50; ++i) add_sphere(w, 0.02 * i, 12.0, 1e-3);
  for (int t = 0; t < 60; ++t) w.step();
  const Residual res = brute_force_residual(w);
  EXPECT_EQ(res.nan_count, 0u);
  EXPECT_LT(res.max_pen_over_radius, 0.05);
}

TEST(WorldHardCases, CoincidentCentresSeparateDeterministically) {
  auto run = [] {
    World w(budget(8), test_table(), weight_policy(params::PushMode::ratio, 100.0));
    const ObjectId a = add_sphere(w, 3.0, 4.0);
    const ObjectId b = add_sphere(w, 3.0, 4.0);
    w.step();
    return std::pair{w.position(a), w.position(b)};
  };
  const auto [a1, b1] = run();
  const auto [a2, b2] = run();
  ASSERT_TRUE(is_finite(a1) && is_finite(b1));
  EXPECT_NEAR(distance_xy(a1, b1), 0.7, 1e-12);
  EXPECT_EQ(a1, a2);
  EXPECT_EQ(b1, b2);
  // Equal parameters: each moved half the depth, in opposite directions.
  EXPECT_NEAR(distance_xy(a1, {3.0, 4.0, 0.0}), 0.35, 1e-12);
}

// A body spawned inside a low, wide obstacle: the shortest way out is up, which a grounded body
// cannot take; it must be pushed out sideways. A body standing on a ledge must stay on it.
TEST(WorldHardCases, EmbeddedBodyLeavesSidewaysAndLedgeStandersStay) {
  World w(budget(8), test_table(), weight_policy(params::PushMode::ratio, 100.0));
  w.add_fixed_cylinder({0.0, 0.0, 0.5}, 1.5, 0.5);           // 1 m tall, 3 m wide
  w.add_fixed_box({10.0, 0.0, 0.5}, {2.0, 2.0, 0.5}, 0.0);   // a ledge, top at z = 1
  const ObjectId embedded = add_sphere(w, 0.4, 0.3, 0.35);
  BodyDef on_ledge;
  on_ledge.position = {10.0, 0.0, 1.0 + 0.35};
  on_ledge.radius_m = 0.35;
  const ObjectId stander = w.create_body(on_ledge);
  w.step();
  const Vec3 p = w.position(embedded);
  EXPECT_GE(std::hypot(p.x, p.y), 1.5 + 0.35 - 1e-9);
  EXPECT_EQ(w.position(stander).x, 10.0);
  EXPECT_EQ(w.position(stander).y, 0.0);
  for (std::size_t i = 0; i < w.body_count(); ++i) EXPECT_LE(w.scenery_max_penetration(i), 1e-9);
}

TEST(WorldHardCases, TenKilometresFromTheOrigin) {
  World w(budget(8), test_table(), weight_policy(params::PushMode::ratio, 100.0));
  const double far = 10000.0;
  const ObjectId a = add_sphere(w, far, far, 1e-3);
  const ObjectId b = add_sphere(w, far + 1.5e-3, far, 1e-3);
  w.step();
  EXPECT_NEAR(distance_xy(w.position(a), w.position(b)), 2e-3, 1e-9);  // 1 um at 10 km
}

TEST(WorldHardCases, ChargingHorseDoesNotTunnelThroughThinWall) {
  World w(budget(8), test_table(), weight_policy(params::PushMode::ratio, 100.0));
  w.add_fixed_box({0.0, 0.0, 1.5}, {0.025, 10.0, 1.5}, 0.0);  // 5 cm thick wall at x = 0
  BodyDef horse;
  horse.position = {-1.0, 0.0, 1.3};
  horse.radius_m = 0.7;
  horse.half_height_m = 0.6;
  horse.archetype = "heavy";
  const ObjectId h = w.create_body(horse);
  for (int t = 0; t < 30; ++t) {
    w.set_desired_velocity(h, {120.0, 0.0, 0.0});  // 2 m per tick at 60 Hz: speed*dt >> radius
    w.step();
    ASSERT_LE(w.position(h).x, -0.025 - 0.7 + 1e-6) << "tick " << t;
  }
}

TEST(WorldHardCases, NonFiniteInputIsRejectedAndChangesNothing) {
  World w(budget(8), test_table(), weight_policy(params::PushMode::ratio, 100.0));
  const ObjectId a = add_sphere(w, 0.0, 0.0);
  const std::uint64_t before = w.state_hash();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(w.set_desired_velocity(a, {nan, 0.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(w.set_desired_velocity(a, {0.0, inf, 0.0}), std::invalid_argument);
  EXPECT_THROW(w.set_position(a, {0.0, 0.0, nan}), std::invalid_argument);
  EXPECT_THROW(w.set_param(a, params::Param::weight_kg, nan), std::invalid_argument);
  EXPECT_THROW(w.set_param(a, params::Param::softness, 2.0), std::invalid_argument);
  BodyDef bad;
  bad.position = {inf, 0.0, 0.0};
  EXPECT_THROW(w.create_body(bad), std::invalid_argument);
  bad.position = {0.0, 0.0, 0.0};
  bad.radius_m = -1.0;
  EXPECT_THROW(w.create_body(bad), std::invalid_argument);
  bad.radius_m = 0.35;
  bad.archetype = "no_such_archetype";
  EXPECT_THROW(w.create_body(bad), std::invalid_argument);
  EXPECT_THROW(w.set_desired_velocity(ObjectId{12345}, {0.0, 0.0, 0.0}), std::invalid_argument);
  EXPECT_EQ(w.body_count(), 1u);
  EXPECT_EQ(w.state_hash(), before);
}

TEST(WorldHardCases, EmptyWorldAndLastBodyDestroyed) {
  World w(budget(8), test_table(), weight_policy(params::PushMode::ratio, 100.0));
  w.step();
  w.add_fixed_box({0.0, 0.0, 1.0}, {1.0, 1.0, 1.0}, 0.0);
  w.step();
  const ObjectId a = add_sphere(w, 5.0, 0.0);
  w.step();
  w.destroy_body(a);
  w.step();
  EXPECT_EQ(w.tick(), 4u);
  EXPECT_EQ(w.body_count(), 0u);
  EXPECT_FALSE(w.is_body(a));
}

TEST(WorldHardCases, StaleIdsAreRejected) {
  World w(budget(8), test_table(), weight_policy(params::PushMode::ratio, 100.0));
  const ObjectId a = add_sphere(w, 0.0, 0.0);
  w.destroy_body(a);
  const ObjectId b = add_sphere(w, 1.0, 0.0);  // reuses a's slot with a new generation
  EXPECT_EQ(a.index(), b.index());
  EXPECT_NE(a, b);
  EXPECT_THROW(w.position(a), std::invalid_argument);
  EXPECT_EQ(w.position(b).x, 1.0);
}

}  // namespace
}  // namespace throng
