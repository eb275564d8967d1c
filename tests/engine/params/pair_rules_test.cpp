#include "throng/params/pair_rules.h"

#include <gtest/gtest.h>

#include <random>

#include "params_test_util.h"

namespace throng::params {
namespace {

using test::share_of_a;

// The patent's example, heavy rule first so it wins over the general one.
std::vector<PairRule> patent_rules() {
  PairRule heavy;
  heavy.name = "player_vs_heavy_npc";
  heavy.a.character_types = category_bit(CharacterType::player);
  heavy.b.character_types = category_bit(CharacterType::npc);
  heavy.b.weight_min_kg = weight_class_kg(WeightClass::heavy);
  heavy.share_b = 0.8;
  PairRule any;
  any.name = "player_vs_npc";
  any.a.character_types = category_bit(CharacterType::player);
  any.b.character_types = category_bit(CharacterType::npc);
  any.share_b = 1.0;
  return {heavy, any};
}

TEST(ParamsPairRules, PlayerPushesNpcFullyButHeavyNpcOnlyEightyPercent) {
  const std::vector<PairRule> rules = patent_rules();
  // Terms that would otherwise favour the NPC, to show that rules take precedence over the mode.
  const PushPolicy policy(PushMode::ratio, {Term{TermInput::weight_kg, 1.0, 100.0}}, rules);
  ObjectParams pc = test::player();
  pc.weight_kg = weight_class_kg(WeightClass::medium);
  const double heavy_share = rules[0].share_b;
  const double full_share = rules[1].share_b;
  for (WeightClass c : {WeightClass::light, WeightClass::medium, WeightClass::heavy, WeightClass::very_heavy}) {
    const ObjectParams n = test::npc(weight_class_kg(c));
    const double expected_npc = c >= WeightClass::heavy ? heavy_share : full_share;
    EXPECT_DOUBLE_EQ(share_of_a(policy, n, pc), expected_npc) << weight_class_name(c);
    EXPECT_DOUBLE_EQ(share_of_a(policy, pc, n), 1.0 - expected_npc) << weight_class_name(c);
  }
  EXPECT_DOUBLE_EQ(share_of_a(policy, pc, test::npc(weight_class_kg(WeightClass::medium))), 0.0);
  EXPECT_DOUBLE_EQ(share_of_a(policy, test::npc(weight_class_kg(WeightClass::heavy)), pc), 0.8);
  // NPC vs NPC: no rule, the ratio applies.
  const double r = share_of_a(policy, test::npc(50.0), test::npc(200.0));
  EXPECT_GT(r, 0.5);
  EXPECT_LT(r, 1.0);
}

TEST(ParamsPairRules, FirstMatchingRuleWins) {
  std::vector<PairRule> rules = patent_rules();
  std::swap(rules[0], rules[1]);  // the general rule first now shadows the heavy one
  const PushPolicy policy(PushMode::ratio, {}, rules);
  EXPECT_DOUBLE_EQ(share_of_a(policy, test::npc(600.0), test::player()), rules[0].share_b);
}

TEST(ParamsPairRules, FixedBodiesNeverReachTheRules) {
  PairRule r;
  r.name = "everything";
  r.share_b = 0.3;
  const PushPolicy policy(PushMode::ratio, {}, {r});
  ObjectParams wall;
  wall.fixed = true;
  EXPECT_EQ(share_of_a(policy, test::npc(), wall), 1.0);
  EXPECT_DOUBLE_EQ(share_of_a(policy, test::npc(), test::npc()), 1.0 - r.share_b);
}

TEST(ParamsPairRules, PredicatesOnFactionRangesAndWeightBounds) {
  SidePredicate p;
  p.relations = category_bit(FactionRelation::enemy);
  p.weight_max_kg = weight_class_kg(WeightClass::heavy);
  p.ranges.push_back({Param::hp, 10.0, 50.0});
  ObjectParams o = test::npc(weight_class_kg(WeightClass::heavy));
  o.faction = 2;
  o.hp = 10.0;
  EXPECT_TRUE(p.matches(o, 1));
  EXPECT_FALSE(p.matches(o, 2));  // same faction as home: ally
  o.hp = 50.5;
  EXPECT_FALSE(p.matches(o, 1));
  o.hp = 50.0;
  o.weight_kg = weight_class_kg(WeightClass::very_heavy);
  EXPECT_FALSE(p.matches(o, 1));
}

// The cached masks must give the same answer as evaluating the predicates directly.
TEST(ParamsPairRules, CachedMasksAgreeWithThePredicates) {
  std::vector<PairRule> rules = patent_rules();
  PairRule enemy_giant;
  enemy_giant.name = "enemy_giant";
  enemy_giant.a.kinds = category_bit(Kind::giant);
  enemy_giant.a.relations = category_bit(FactionRelation::enemy);
  enemy_giant.b.ranges.push_back({Param::importance, 0.0, 4.0});
  enemy_giant.share_b = 0.9;
  rules.insert(rules.begin() + 1, enemy_giant);
  const std::uint32_t home = 1;
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> pick(0, 3);
  auto random_object = [&] {
    ObjectParams o;
    o.character_type = static_cast<CharacterType>(pick(rng));
    o.kind = static_cast<Kind>(pick(rng) + 1);
    o.weight_kg = weight_class_kg(static_cast<WeightClass>(pick(rng)));
    o.faction = static_cast<std::uint8_t>(pick(rng) % 3);
    o.importance = 2.0 * pick(rng);
    return o;
  };
  for (int i = 0; i < 2000; ++i) {
    const ObjectParams a = random_object();
    const ObjectParams b = random_object();
    std::uint32_t al = 0, ar = 0, bl = 0, br = 0;
    compute_rule_masks(rules, a, home, al, ar);
    compute_rule_masks(rules, b, home, bl, br);
    EXPECT_EQ(resolve_rule_masks(rules, al, ar, bl, br), match_pair_rules(rules, a, b, home));
  }
}

}  // namespace
}  // namespace throng::params
