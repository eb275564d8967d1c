// Every example of the seed patent, at the level of the world: set the parameters, overlap the
// bodies, step once, and check how far each body was pushed.
#include <gtest/gtest.h>

#include <cmath>

#include "throng/params/soft_push.h"
#include "world/world_fixtures.h"

namespace throng {
namespace {

using namespace throng::test;

// FIG. 7: the virtual plane VP1 sits at the 4:1 point. Resistance ratio 4:1 comes from a weight
// difference of scale * ln 4 under the policy's exp(weighted sum) rule.
TEST(WorldPatent, Fig7FourToOnePlane) {
  const double scale = 60.0 / std::log(4.0);
  World w(quiet_settings(), test_table(), weight_policy(params::PushMode::ratio, scale));
  const ObjectId a = add_sphere(w, 0.0, 0.0, 0.35, "infantry");  // 80 kg
  const ObjectId b = add_sphere(w, 0.6, 0.0, 0.35, "infantry");
  w.set_param(b, params::Param::weight_kg, 140.0);  // +60 kg = scale * ln 4 -> 4x resistance
  const double depth = 0.7 - 0.6;
  w.step();
  const double moved_a = -w.position(a).x;
  const double moved_b = w.position(b).x - 0.6;
  EXPECT_NEAR(moved_a, 0.8 * depth, 1e-12);
  EXPECT_NEAR(moved_b, 0.2 * depth, 1e-12);
  EXPECT_NEAR(distance_xy(w.position(a), w.position(b)), 0.7, 1e-12);
  ASSERT_EQ(w.push_events().size(), 1u);
  EXPECT_NEAR(w.push_events()[0].share_a, 0.8, 1e-6);
}

// FIG. 5(b) / 6(a,b): conventional priority baseline, the lower priority body moves 100%.
TEST(WorldPatent, PriorityBaselineLoserMovesAll) {
  World w(quiet_settings(), test_table(), weight_policy(params::PushMode::priority, 100.0));
  const ObjectId light = add_sphere(w, 0.0, 0.0, 0.35, "light");
  const ObjectId heavy = add_sphere(w, 0.5, 0.0, 0.35, "heavy");
  w.step();
  EXPECT_NEAR(w.position(light).x, -0.2, 1e-12);
  EXPECT_EQ(w.position(heavy).x, 0.5);
}

// FIG. 6(e,f): conventional 50/50 baseline, the plane in the middle of the depth.
TEST(WorldPatent, HalfBaselineSplitsEvenly) {
  World w(quiet_settings(), test_table(), weight_policy(params::PushMode::half, 100.0));
  const ObjectId light = add_sphere(w, 0.0, 0.0, 0.35, "light");
  const ObjectId heavy = add_sphere(w, 0.5, 0.0, 0.35, "heavy");
  w.step();
  EXPECT_NEAR(w.position(light).x, -0.1, 1e-12);
  EXPECT_NEAR(w.position(heavy).x, 0.6, 1e-12);
}

// FIG. 6(c,d): T1 overlaps fixed T2 and T3 at once and is pushed out of both planes.
TEST(WorldPatent, BodyPushedOutOfTwoFixedBodies) {
  World w(quiet_settings(), test_table(), weight_policy(params::PushMode::ratio, 100.0));
  // Two walls meeting at a right angle: x <= 0 and y <= 0 are solid.
  w.add_fixed_box({-1.0, 2.0, 1.0}, {1.0, 3.0, 1.0}, 0.0);
  w.add_fixed_box({2.0, -1.0, 1.0}, {3.0, 1.0, 1.0}, 0.0);
  const ObjectId t1 = add_sphere(w, 0.2, 0.25, 0.35);  // 0.15 into the first, 0.10 into the second
  w.step();
  const Vec3 p = w.position(t1);
  EXPECT_NEAR(p.x, 0.35, 1e-9);
  EXPECT_NEAR(p.y, 0.35, 1e-9);
  EXPECT_LE(w.scenery_max_penetration(0), 1e-9);
}

// FIG. 10(b,c): a soft fixed body pushes a deeper mover out by a larger amount, but gradually.
TEST(WorldPatent, SoftFixedBodyDeeperMeansLargerPush) {
  auto push_after_one_tick = [](double depth) {
    World w(quiet_settings(), test_table(), weight_policy(params::PushMode::ratio, 100.0));
    w.add_fixed_box({-1.0, 0.0, 1.0}, {1.0, 5.0, 1.0}, 0.0, "bush");  // face at x = 0
    const ObjectId m = add_sphere(w, 0.35 - depth, 0.0, 0.35);
    w.step();
    return w.position(m).x - (0.35 - depth);
  };
  const double shallow = push_after_one_tick(0.05);
  const double deep = push_after_one_tick(0.15);
  EXPECT_GT(shallow, 0.0);
  EXPECT_GT(deep, shallow);
  EXPECT_LT(shallow, 0.05);  // not pushed out in one tick: it sinks in
  EXPECT_LT(deep, 0.15);
  // Expected from the soft formula: push = depth * share(depth).
  EXPECT_NEAR(deep, 0.15 * params::soft_push_share(0.6, 0.15, 0.35), 1e-9);
}

TEST(WorldPatent, SoftFixedBodyPushesOutOverSeveralTicks) {
  World w(quiet_settings(), test_table(), weight_policy(params::PushMode::ratio, 100.0));
  w.add_fixed_box({-1.0, 0.0, 1.0}, {1.0, 5.0, 1.0}, 0.0, "bush");
  const ObjectId m = add_sphere(w, 0.35 - 0.2, 0.0, 0.35);
  int ticks = 0;
  double last_depth = 0.2;
  while (ticks < 200) {
    w.step();
    ++ticks;
    const double depth = 0.35 - w.position(m).x;
    EXPECT_LT(depth, last_depth);  // monotone: never pushed deeper, never overshoots
    EXPECT_GE(depth, -1e-12);
    last_depth = depth;
    if (depth < 0.002) break;
  }
  EXPECT_GT(ticks, 3);   // gradual, not one tick
  EXPECT_LT(ticks, 200);  // but it does come out
}

// The patent's pair-rule example: player vs NPC pushes the NPC 100%, a heavy NPC only 80%.
TEST(WorldPatent, PlayerVsNpcAndHeavyNpc) {
  params::PairRule heavy;
  heavy.name = "player vs heavy npc";
  heavy.a.character_types = params::category_bit(params::CharacterType::player);
  heavy.b.character_types = params::category_bit(params::CharacterType::npc);
  heavy.b.weight_min_kg = 200.0;
  heavy.share_b = 0.8;
  params::PairRule any = heavy;
  any.name = "player vs npc";
  any.b.weight_min_kg = 0.0;
  any.share_b = 1.0;
  const params::PushPolicy policy(params::PushMode::ratio, {}, {heavy, any});
  World w(quiet_settings(), test_table(), policy);
  const ObjectId player = add_sphere(w, 0.0, 0.0, 0.35, "player");
  const ObjectId npc = add_sphere(w, 0.6, 0.0, 0.35, "infantry");
  const ObjectId player2 = add_sphere(w, 0.0, 10.0, 0.35, "player");
  const ObjectId big = add_sphere(w, 0.6, 10.0, 0.35, "npc_heavy");
  w.step();
  EXPECT_EQ(w.position(player).x, 0.0);
  EXPECT_NEAR(w.position(npc).x - 0.6, 0.1, 1e-12);
  EXPECT_NEAR(-w.position(player2).x, 0.2 * 0.1, 1e-12);
  EXPECT_NEAR(w.position(big).x - 0.6, 0.8 * 0.1, 1e-12);
}

// "The opposite result": inverting the weight term makes the heavy body the one pushed more.
TEST(WorldPatent, InvertedParameterFlipsWhoMovesMore) {
  for (bool invert : {false, true}) {
    World w(quiet_settings(), test_table(), weight_policy(params::PushMode::ratio, 100.0, invert));
    const ObjectId light = add_sphere(w, 0.0, 0.0, 0.35, "light");
    const ObjectId heavy = add_sphere(w, 0.6, 0.0, 0.35, "heavy");
    w.step();
    const double moved_light = -w.position(light).x;
    const double moved_heavy = w.position(heavy).x - 0.6;
    const double expected_light_share = invert ? 1.0 / (1.0 + std::exp(1.5)) : 1.0 / (1.0 + std::exp(-1.5));
    EXPECT_NEAR(moved_light, 0.1 * expected_light_share, 1e-12) << "invert=" << invert;
    if (invert) EXPECT_GT(moved_heavy, moved_light);
    else EXPECT_LT(moved_heavy, moved_light);
  }
}

TEST(WorldPatent, PassThroughBodiesNeverCollide) {
  World w(quiet_settings(), test_table(), weight_policy(params::PushMode::ratio, 100.0));
  const ObjectId ghost = add_sphere(w, 0.0, 0.0, 0.35, "ghost");
  const ObjectId soldier = add_sphere(w, 0.1, 0.0, 0.35, "infantry");
  w.step();
  EXPECT_EQ(w.position(ghost).x, 0.0);
  EXPECT_EQ(w.position(soldier).x, 0.1);
  EXPECT_TRUE(w.push_events().empty());
}

// Parameters change while the match runs: a runtime weight change moves the plane next tick.
TEST(WorldPatent, RuntimeParameterChangeMovesThePlane) {
  World w(quiet_settings(), test_table(), weight_policy(params::PushMode::ratio, 100.0));
  const ObjectId a = add_sphere(w, 0.0, 0.0);
  const ObjectId b = add_sphere(w, 0.6, 0.0);
  w.step();
  EXPECT_NEAR(-w.position(a).x, 0.05, 1e-12);  // equal weights: 50/50
  w.set_position(a, {0.0, 0.0, 0.35});
  w.set_position(b, {0.6, 0.0, 0.35});
  w.set_param(b, params::Param::weight_kg, 80.0 + 100.0 * std::log(3.0));
  w.step();
  EXPECT_NEAR(-w.position(a).x, 0.75 * 0.1, 1e-12);
}

}  // namespace
}  // namespace throng
