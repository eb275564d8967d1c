// The SceneDriver's behaviors: seek stops on the target, march keeps going, idle stands.
#include <gtest/gtest.h>

#include <cmath>

#include "throng/scene/build_scene.h"
#include "throng/scene/scene_driver.h"
#include "throng/scene/scene_error.h"

namespace throng::scene {
namespace {

constexpr double kDt = 1.0 / 60.0;

TEST(SceneDriver, SeekSpeedIsCappedAtDistanceOverDt) {
  const ResolvedBehavior seek{BehaviorKind::seek_point, {3.0, 4.0}, {}, 1.5};
  // Far away: full speed towards the target (direction (3, 4) / 5).
  const Vec3 far = desired_velocity(seek, {0.0, 0.0, 1.0}, kDt);
  EXPECT_DOUBLE_EQ(far.x, 1.5 * 0.6);
  EXPECT_DOUBLE_EQ(far.y, 1.5 * 0.8);
  EXPECT_EQ(far.z, 0.0);
  // 1 cm away: speed = 0.01 / dt = 0.6 m/s < 1.5, so one tick lands on the target.
  const Vec3 near = desired_velocity(seek, {3.0, 3.99, 0.0}, kDt);
  EXPECT_NEAR(near.y * kDt, 0.01, 1e-15);
  EXPECT_NEAR(near.x, 0.0, 1e-12);
  // On the target: stand still.
  const Vec3 on = desired_velocity(seek, {3.0, 4.0, 0.0}, kDt);
  EXPECT_EQ(on.x, 0.0);
  EXPECT_EQ(on.y, 0.0);
}

TEST(SceneDriver, MarchAndIdle) {
  const ResolvedBehavior march{BehaviorKind::march, {}, {0.0, -1.0}, 2.0};
  const Vec3 v = desired_velocity(march, {100.0, 100.0, 0.0}, kDt);
  EXPECT_EQ(v.x, 0.0);
  EXPECT_EQ(v.y, -2.0);
  EXPECT_EQ(desired_velocity(ResolvedBehavior{}, {1.0, 2.0, 3.0}, kDt), Vec3{});
}

TEST(SceneDriver, MarchTargetGivesDirectionFromShapeCentre) {
  SpawnShape shape;
  shape.kind = SpawnAreaKind::rect;
  shape.centre = {-10.0, 5.0};
  Behavior b{BehaviorKind::march, {20.0, -35.0}, true, {}, 1.0};  // (30, -40) away: direction (0.6, -0.8)
  const auto r = resolve_behavior(b, shape, "spawns[0].behaviour");
  EXPECT_DOUBLE_EQ(r.direction.x, 0.6);
  EXPECT_DOUBLE_EQ(r.direction.y, -0.8);
  b.target = shape.centre;
  EXPECT_THROW((void)resolve_behavior(b, shape, "spawns[0].behaviour"), SceneError);
}

// In a real World: a lone body seeking a point arrives and then stays within a hair of it.
TEST(SceneDriver, BodyStopsAtTheTarget) {
  SceneDef s;
  SpawnGroup g;
  g.count = 1;
  g.shape.kind = SpawnAreaKind::point;
  g.shape.centre = {0.0, 0.0};
  g.behavior = {BehaviorKind::seek_point, {1.0, 0.5}, true, {}, 1.5};
  s.spawns.push_back(g);
  BuiltScene b = build_scene(s);
  const ObjectId id = b.body_ids.at(0);
  const double dist0 = std::hypot(1.0, 0.5);
  // Time at full speed, plus the one tick the cap may add.
  const int ticks = static_cast<int>(std::ceil(dist0 / (1.5 * s.settings.dt_s))) + 1;
  for (int t = 0; t < ticks; ++t) step_scene(b);
  Vec3 p = b.world.position(id);
  EXPECT_NEAR(p.x, 1.0, 1e-9);
  EXPECT_NEAR(p.y, 0.5, 1e-9);
  for (int t = 0; t < 30; ++t) step_scene(b);  // and stays there: no overshoot, no oscillation
  p = b.world.position(id);
  EXPECT_NEAR(p.x, 1.0, 1e-9);
  EXPECT_NEAR(p.y, 0.5, 1e-9);
}

TEST(SceneDriver, AgentsAreVisitedInIdOrder) {
  SceneDriver d(kDt);
  const auto beh = d.add_behaviour({});
  d.add_agent(ObjectId{7}, beh);
  d.add_agent(ObjectId{3}, beh);
  d.add_agent(ObjectId{5}, beh);
  ASSERT_EQ(d.agents().size(), 3u);
  EXPECT_EQ(d.agents()[0].id.value, 3u);
  EXPECT_EQ(d.agents()[1].id.value, 5u);
  EXPECT_EQ(d.agents()[2].id.value, 7u);
}

}  // namespace
}  // namespace throng::scene
