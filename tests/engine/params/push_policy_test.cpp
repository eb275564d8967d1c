#include "throng/params/push_policy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "params_test_util.h"

namespace throng::params {
namespace {

using test::share_of_a;
using test::single_term;
using test::view;

// FIG. 7: the virtual plane splits the depth 4:1. Resistances 1 : 4 mean a is 4x easier to push.
TEST(ParamsPolicy, Fig7FourToOnePlane) {
  const double ra = 1.0;
  const double rb = 4.0;
  EXPECT_DOUBLE_EQ(share_a_fast(ra, rb), rb / (ra + rb));
  EXPECT_DOUBLE_EQ(share_a_fast(ra, rb), 0.8);
  EXPECT_DOUBLE_EQ(share_a_fast(rb, ra), 0.2);
  EXPECT_DOUBLE_EQ(PushPolicy::share_a_fast(ra, rb), 0.8);

  // The same plane from parameters: one term whose score difference is ln 4.
  const PushPolicy policy = single_term(TermInput::importance, std::log(4.0), 1.0);
  ObjectParams a;
  ObjectParams b;
  a.importance = 0.0;
  b.importance = 1.0;
  const GroupTable groups;
  EXPECT_DOUBLE_EQ(policy.coefficients(a, groups).resistance, 1.0);
  EXPECT_NEAR(policy.coefficients(b, groups).resistance, 4.0, 1e-12);
  EXPECT_NEAR(share_of_a(policy, a, b), 0.8, 1e-12);
  EXPECT_NEAR(share_of_a(policy, b, a), 0.2, 1e-12);
}

TEST(ParamsPolicy, RatioFollowsTheWeightedScore) {
  const double w = 1.5;
  const double scale = 100.0;
  const PushPolicy policy = single_term(TermInput::weight_kg, w, scale);
  const ObjectParams light = test::npc(weight_class_kg(WeightClass::medium));
  const ObjectParams heavy = test::npc(weight_class_kg(WeightClass::heavy));
  const double m_light = std::exp(w * light.weight_kg / scale);
  const double m_heavy = std::exp(w * heavy.weight_kg / scale);
  const double expected = m_heavy / (m_light + m_heavy);
  EXPECT_NEAR(share_of_a(policy, light, heavy), expected, 1e-12);
  EXPECT_GT(share_of_a(policy, light, heavy), 0.5);  // the light body is pushed more
  EXPECT_NEAR(share_of_a(policy, light, heavy) + share_of_a(policy, heavy, light), 1.0, 1e-15);
}

TEST(ParamsPolicy, InvertFlipsWhichSideIsPushedMore) {
  const PushPolicy normal = single_term(TermInput::weight_kg, 1.0, 100.0, false);
  const PushPolicy inverted = single_term(TermInput::weight_kg, 1.0, 100.0, true);
  const ObjectParams light = test::npc(50.0);
  const ObjectParams heavy = test::npc(200.0);
  const double s_normal = share_of_a(normal, light, heavy);
  const double s_inverted = share_of_a(inverted, light, heavy);
  EXPECT_GT(s_normal, 0.5);
  EXPECT_LT(s_inverted, 0.5);
  // exp(-x) swaps the roles of the two resistances: the shares mirror each other exactly.
  EXPECT_NEAR(s_inverted, 1.0 - s_normal, 1e-12);
}

TEST(ParamsPolicy, HalfBaselineIsFiftyFifty) {
  const PushPolicy policy = single_term(TermInput::weight_kg, 5.0, 1.0, false, PushMode::half);
  EXPECT_EQ(share_of_a(policy, test::npc(50.0), test::npc(600.0)), 0.5);
  EXPECT_EQ(share_of_a(policy, test::npc(600.0), test::npc(50.0)), 0.5);
}

TEST(ParamsPolicy, PriorityBaselineMovesTheLowerScoreFully) {
  const PushPolicy policy = single_term(TermInput::weight_kg, 1.0, 100.0, false, PushMode::priority);
  const GroupTable groups;
  const ObjectParams light = test::npc(50.0);
  const ObjectParams heavy = test::npc(200.0);
  EXPECT_EQ(share_of_a(policy, light, heavy), 1.0);
  EXPECT_EQ(share_of_a(policy, heavy, light), 0.0);
  // Ties: the lower caller-supplied id moves, whichever argument it is.
  const ObjectParams twin = test::npc(80.0);
  const PairView low = view(policy, twin, groups, 3);
  const PairView high = view(policy, twin, groups, 9);
  EXPECT_EQ(policy.share_a(low, high), 1.0);
  EXPECT_EQ(policy.share_a(high, low), 0.0);
}

TEST(ParamsPolicy, FixedBodyTakesNothingInEveryMode) {
  const GroupTable groups;
  ObjectParams wall;
  wall.fixed = true;
  wall.weight_kg = 50.0;  // even lighter than the mover: fixed wins regardless of terms
  const ObjectParams mover = test::npc(600.0);
  for (PushMode mode : {PushMode::ratio, PushMode::priority, PushMode::half}) {
    const PushPolicy policy = single_term(TermInput::weight_kg, 1.0, 100.0, false, mode);
    EXPECT_EQ(policy.coefficients(wall, groups).resistance, kFixedResistance);
    EXPECT_EQ(share_of_a(policy, mover, wall), 1.0) << push_mode_name(mode);
    EXPECT_EQ(share_of_a(policy, wall, mover), 0.0) << push_mode_name(mode);
    EXPECT_THROW((void)share_of_a(policy, wall, wall), std::logic_error);
  }
}

// Found by fuzzing (world checkpoints): two inputs that each overflow over their scale (a height
// and a camera distance near the largest double) gave inf - inf, a NaN score, and the next step
// threw. Each input over its scale is bounded far beyond real values, so the score is finite.
TEST(ParamsPolicy, TwoOverflowingInputsGiveAFiniteScoreNotNaN) {
  const PushPolicy policy(PushMode::ratio,
                          {Term{TermInput::height_above_ground_m, 1.0, 0.5, false},
                           Term{TermInput::camera_distance_m, 1.0, 0.5, true}},
                          {});
  const GroupTable groups;
  ObjectParams o;
  o.height_above_ground_m = 1.7e308;
  o.camera_distance_m = 1.7e308;
  EXPECT_EQ(policy.static_score(o, groups), 0.0);
  o.camera_distance_m = 1.0;
  EXPECT_EQ(policy.static_score(o, groups), kScoreClamp);
}

TEST(ParamsPolicy, ScoreIsClampedAndSharesStayStrictlyInside) {
  const PushPolicy policy = single_term(TermInput::height_above_ground_m, 1000.0, 1.0);
  const GroupTable groups;
  ObjectParams high;
  high.height_above_ground_m = param_range(Param::height_above_ground_m).max;
  ObjectParams low;
  low.height_above_ground_m = param_range(Param::height_above_ground_m).min;
  EXPECT_EQ(policy.static_score(high, groups), kScoreClamp);
  EXPECT_EQ(policy.static_score(low, groups), -kScoreClamp);
  EXPECT_EQ(policy.coefficients(high, groups).resistance, std::exp(kScoreClamp));
  // 1 / (1 + e^-40) rounds to exactly 1.0 in double; the share clamp keeps both sides moving.
  const double s = share_of_a(policy, low, high);
  EXPECT_EQ(s, kMaxShare);
  EXPECT_LT(s, 1.0);
  EXPECT_GT(1.0 - s, 0.0);
  EXPECT_EQ(share_of_a(policy, high, low), kMinShare);
  EXPECT_GT(kMinShare, 0.0);
}

TEST(ParamsPolicy, FactionTermPushesEnemiesMore) {
  const double w = 0.7;
  const PushPolicy policy = single_term(TermInput::faction, w, 1.0);
  ObjectParams ally;
  ally.faction = static_cast<std::uint8_t>(policy.home_faction());
  ObjectParams enemy;
  enemy.faction = static_cast<std::uint8_t>(policy.home_faction() + 1);
  ObjectParams neutral;
  neutral.faction = static_cast<std::uint8_t>(kNeutralFaction);
  // ally +1, enemy -1: score difference 2w.
  EXPECT_NEAR(share_of_a(policy, enemy, ally), 1.0 / (1.0 + std::exp(-2.0 * w)), 1e-12);
  EXPECT_NEAR(share_of_a(policy, neutral, ally), 1.0 / (1.0 + std::exp(-w)), 1e-12);
  EXPECT_FALSE(policy.has_pair_dependent_terms());  // folded into the cached resistance
}

TEST(ParamsPolicy, FacingTermIsPairDependent) {
  const double w = 1.2;
  const PushPolicy policy = single_term(TermInput::facing, w, 1.0);
  ASSERT_TRUE(policy.has_pair_dependent_terms());
  const GroupTable groups;
  ObjectParams braced;  // faces +x, toward the other
  braced.set_facing(1.0, 0.0);
  ObjectParams turned;  // also faces +x, i.e. shows its back to the body at -x
  turned.set_facing(1.0, 0.0);
  const PairView a = view(policy, braced, groups, 1, 1.0, 0.0, 0.0);
  const PairView b = view(policy, turned, groups, 2, -1.0, 0.0, 0.0);
  // dot values: +1 and -1, so s_a - s_b = 2w and a is the harder one to push.
  EXPECT_NEAR(policy.share_a(a, b), 1.0 / (1.0 + std::exp(2.0 * w)), 1e-12);
  EXPECT_NEAR(policy.share_a(b, a), 1.0 / (1.0 + std::exp(-2.0 * w)), 1e-12);
  PairView no_params = a;
  no_params.params = nullptr;
  EXPECT_THROW((void)policy.share_a(no_params, b), std::logic_error);
}

TEST(ParamsPolicy, MoraleTermNeedsTheGroupTable) {
  const PushPolicy policy = single_term(TermInput::morale, 1.0, 10.0);
  GroupTable groups;
  groups.set(1, Group{});
  ObjectParams a;
  a.group_id = 1;
  const ObjectParams b;
  const PairView va = view(policy, a, groups, 1);
  const PairView vb = view(policy, b, groups, 2, -1.0);
  EXPECT_THROW((void)policy.share_a(va, vb), std::logic_error);
  EXPECT_DOUBLE_EQ(policy.share_a(va, vb, groups), 0.5);  // both neutral morale
}

TEST(ParamsPolicy, GroupTermsReadTheObjectsGroup) {
  const PushPolicy policy = single_term(TermInput::group_member_count, 1.0, 100.0);
  GroupTable groups;
  Group big;
  big.member_count = 300;
  groups.set(2, big);
  ObjectParams member;
  member.group_id = 2;
  const ObjectParams loner;
  EXPECT_DOUBLE_EQ(policy.static_score(member, groups), 1.0 * big.member_count / 100.0);
  EXPECT_EQ(policy.static_score(loner, groups), 0.0);
}

TEST(ParamsPolicy, ConstructorValidationNamesTheField) {
  using test::config_error_of;
  EXPECT_EQ(config_error_of([] { PushPolicy(PushMode::ratio, {Term{TermInput::hp, 1.0, 0.0}}, {}); }).path(),
            "terms[0].scale");
  EXPECT_EQ(config_error_of([] {
              PushPolicy(PushMode::ratio,
                         {Term{TermInput::hp, 1.0, 1.0}, Term{TermInput::level, std::nan(""), 1.0}}, {});
            }).path(),
            "terms[1].weight");
  EXPECT_EQ(config_error_of([] {
              PushPolicy(PushMode::ratio, {Term{TermInput::hp, 1.0, 1.0}, Term{TermInput::hp, 2.0, 1.0}}, {});
            }).path(),
            "terms[1].param");
  EXPECT_EQ(config_error_of([] { PushPolicy(PushMode::ratio, {}, {}, 0); }).path(), "home_faction");
  EXPECT_EQ(config_error_of([] {
              PushPolicy(PushMode::ratio, {}, {PairRule{"r", {}, {}, 1.5}});
            }).path(),
            "pair_rules[0].share_b");
  std::vector<PairRule> many(kMaxPairRules + 1);
  for (std::size_t i = 0; i < many.size(); ++i) {
    many[i].name = std::to_string(i);  // (not "r" + ...: GCC 12 raises a false -Wrestrict there)
  }
  EXPECT_EQ(config_error_of([&] { PushPolicy(PushMode::ratio, {}, many); }).path(), "pair_rules");
}

}  // namespace
}  // namespace throng::params
