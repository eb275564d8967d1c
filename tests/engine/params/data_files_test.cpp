// The example data files shipped in server/engine/data load and do what their comments say.
#include <gtest/gtest.h>

#include <string>

#include "params_test_util.h"
#include "throng/params/param_table.h"
#include "throng/params/params_json.h"
#include "throng/params/push_policy.h"

#ifndef THRONG_SOURCE_DIR
#error "THRONG_SOURCE_DIR must point at the repository root"
#endif

namespace throng::params {
namespace {

std::string data_path(const char* name) { return std::string(THRONG_SOURCE_DIR) + "/server/engine/data/" + name; }

const PairRule& rule_named(const PushPolicy& p, const std::string& name) {
  for (const PairRule& r : p.rules()) {
    if (r.name == name) return r;
  }
  throw std::runtime_error("no rule " + name);
}

TEST(ParamsDataFiles, DefaultParamsLoad) {
  const ParamTable t = load_param_table(data_path("default_params.json"));
  for (const char* name : {"infantry", "cavalry", "giant", "player", "wall", "bush"}) {
    EXPECT_NE(t.find_archetype(name), nullptr) << name;
  }
  EXPECT_TRUE(t.archetype("wall").fixed);
  EXPECT_EQ(t.archetype("wall").softness, 0.0);
  EXPECT_TRUE(t.archetype("bush").fixed);
  EXPECT_GT(t.archetype("bush").softness, 0.0);
  EXPECT_EQ(t.archetype("player").character_type, CharacterType::player);
  const ObjectParams rider_horse = t.resolve("cavalry", 21, 1);
  EXPECT_EQ(rider_horse.kind, Kind::mount);
  EXPECT_EQ(rider_horse.faction, 2);
  EXPECT_GE(t.groups().size(), 1u);
}

TEST(ParamsDataFiles, PoliciesLoadAndApplyThePatentRule) {
  const ParamTable t = load_param_table(data_path("default_params.json"));
  for (const char* file : {"default_policy.json", "patent_examples_policy.json"}) {
    const PushPolicy p = load_push_policy(data_path(file));
    EXPECT_EQ(p.mode(), PushMode::ratio) << file;
    const ObjectParams pc = t.resolve("player", 1);
    const ObjectParams foot = t.resolve("infantry", 30);
    const ObjectParams horse = t.resolve("cavalry", 31);
    ASSERT_LT(foot.weight_kg, weight_class_kg(WeightClass::heavy));
    ASSERT_GE(horse.weight_kg, weight_class_kg(WeightClass::heavy));
    EXPECT_DOUBLE_EQ(test::share_of_a(p, foot, pc, t.groups()), rule_named(p, "player_vs_npc").share_b) << file;
    EXPECT_DOUBLE_EQ(test::share_of_a(p, horse, pc, t.groups()), rule_named(p, "player_vs_heavy_npc").share_b)
        << file;
    // Among NPCs the ratio applies: a giant gives way less than the infantry it hits.
    const double giant_share = test::share_of_a(p, t.resolve("giant", 32), foot, t.groups());
    EXPECT_GT(giant_share, 0.0) << file;
    EXPECT_LT(giant_share, 0.5) << file;
    // Walls never move.
    EXPECT_EQ(test::share_of_a(p, t.resolve("wall", 33), foot, t.groups()), 0.0) << file;
  }
}

}  // namespace
}  // namespace throng::params
