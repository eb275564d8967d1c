// A few ticks of "play" with the pure pieces the engine strings together: cached coefficients,
// live group morale, and the per-pair share. No geometry: the contact is a fixed pair.
#include <gtest/gtest.h>

#include <cmath>

#include "params_test_util.h"
#include "throng/params/group_table.h"
#include "throng/params/push_policy.h"

namespace throng::params {
namespace {

TEST(ParamsPlay, MoraleChangeFlipsTheShareWithoutRecomputingCoefficients) {
  const Term weight{TermInput::weight_kg, 1.0, 100.0};
  const Term morale{TermInput::morale, 1.0, 10.0};
  const PushPolicy policy(PushMode::ratio, {weight, morale}, {});
  ASSERT_TRUE(policy.has_pair_dependent_terms());

  GroupTable groups;
  groups.set(1, Group{});
  groups.set(2, Group{});
  const MoraleConfig& mc = groups.morale_config();

  ObjectParams a = test::npc(100.0);  // slightly heavier: harder to push at equal morale
  a.group_id = 1;
  ObjectParams b = test::npc(80.0);
  b.group_id = 2;

  // Computed once, as the engine does when parameters change; morale is read live per pair.
  const PairView va = test::view(policy, a, groups, 1, 1.0, 0.0, 0.0);
  const PairView vb = test::view(policy, b, groups, 2, -1.0, 0.0, 0.0);
  auto expected_share_a = [&] {
    const double sa = weight.weight * a.weight_kg / weight.scale + morale.weight * groups.morale(1) / morale.scale;
    const double sb = weight.weight * b.weight_kg / weight.scale + morale.weight * groups.morale(2) / morale.scale;
    return std::exp(sb) / (std::exp(sa) + std::exp(sb));
  };

  const double before = policy.share_a(va, vb, groups);
  EXPECT_NEAR(before, expected_share_a(), 1e-12);
  EXPECT_LT(before, 0.5);

  // Group 1 gets surrounded: 2 allies vs 8 enemies nearby for a few ticks.
  for (int tick = 0; tick < 3; ++tick) {
    groups.update_morale(1, 2, 8);
    groups.update_morale(2, 8, 2);
  }
  ASSERT_EQ(groups.at(1).morale_state, MoraleState::low);
  ASSERT_EQ(groups.at(2).morale_state, MoraleState::high);
  const double routed = policy.share_a(va, vb, groups);
  EXPECT_NEAR(routed, expected_share_a(), 1e-12);
  EXPECT_GT(routed, 0.5);  // flipped: a is now the one that gives way

  // The fight evens out around the dead band: the share holds still instead of flickering.
  const auto total = 100u;
  const auto in_band_lo = static_cast<std::uint32_t>(std::lround(mc.low_enter * total)) + 1u;
  const auto in_band_hi = static_cast<std::uint32_t>(std::lround(mc.low_exit * total)) - 1u;
  for (int tick = 0; tick < 50; ++tick) {
    const std::uint32_t allies = tick % 2 == 0 ? in_band_lo : in_band_hi;
    groups.update_morale(1, allies, total - allies);
    ASSERT_EQ(policy.share_a(va, vb, groups), routed) << "tick " << tick;
  }

  // Reinforcements arrive: morale recovers and the share flips back.
  groups.update_morale(1, 6, 4);
  groups.update_morale(2, 5, 5);
  EXPECT_EQ(groups.at(1).morale_state, MoraleState::normal);
  EXPECT_EQ(groups.at(2).morale_state, MoraleState::normal);
  EXPECT_DOUBLE_EQ(policy.share_a(va, vb, groups), before);
}

}  // namespace
}  // namespace throng::params
