// Property: without pair rules and without fixed bodies, every share of the ratio mode is strictly
// inside (0, 1) on both sides, and swapping the arguments mirrors it — over random parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "params_test_util.h"

namespace throng::params {
namespace {

double uniform_in(std::mt19937_64& rng, Param p) {
  const ParamRange r = param_range(p);
  std::uniform_real_distribution<double> d(r.min, r.max);
  const double v = d(rng);
  return r.integral ? std::floor(v) : v;
}

ObjectParams random_params(std::mt19937_64& rng) {
  ObjectParams o;
  for (Param p : {Param::kind, Param::importance, Param::size_m, Param::weight_kg, Param::equipment_level,
                  Param::speed_mps, Param::facing_yaw_rad, Param::faction, Param::character_type,
                  Param::height_above_ground_m, Param::camera_distance_m, Param::hp, Param::level}) {
    o.set(p, uniform_in(rng, p));
  }
  o.group_id = static_cast<std::uint32_t>(rng() % 4);  // 0 = no group, 1..3 exist
  return o;
}

TEST(ParamsProperty, RatioSharesStrictlyInsideForRandomPairs) {
  std::mt19937_64 rng(0x7468726f6e67ull);  // "throng"
  GroupTable groups;
  for (std::uint32_t id = 1; id <= 3; ++id) {
    Group g;
    g.base_morale = -50.0 + 50.0 * (id - 1);
    g.member_count = 100 * id;
    g.strength = 2.0 * id;
    g.morale_state = static_cast<MoraleState>(id - 1);
    groups.set(id, g);
  }
  // Every term, with weights large enough that many scores hit the clamp.
  std::vector<Term> terms;
  for (std::size_t i = 0; i < kTermInputCount; ++i) {
    terms.push_back(Term{static_cast<TermInput>(i), 0.5 + 2.0 * static_cast<double>(i % 5), 1.0 + i, i % 3 == 0});
  }
  const PushPolicy policy(PushMode::ratio, terms, {});
  for (int i = 0; i < 10000; ++i) {
    const ObjectParams a = random_params(rng);
    const ObjectParams b = random_params(rng);
    std::uniform_real_distribution<double> angle(-3.14159, 3.14159);
    const double t = angle(rng);
    const PairView va = test::view(policy, a, groups, 1, std::cos(t), std::sin(t), 0.0);
    const PairView vb = test::view(policy, b, groups, 2, -std::cos(t), -std::sin(t), 0.0);
    const double s = policy.share_a(va, vb, groups);
    ASSERT_TRUE(s > 0.0 && s < 1.0) << "pair " << i << " share " << s;
    ASSERT_TRUE(1.0 - s > 0.0 && 1.0 - s < 1.0) << "pair " << i;
    ASSERT_NEAR(s + policy.share_a(vb, va, groups), 1.0, 1e-12) << "pair " << i;
    ASSERT_EQ(s, policy.share_a(va, vb, groups));  // pure: same input, same bits
  }
}

}  // namespace
}  // namespace throng::params
