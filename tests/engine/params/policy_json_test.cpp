#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "params_test_util.h"
#include "throng/params/push_policy.h"
#include "throng/params/params_json.h"

namespace throng::params {
namespace {

using nlohmann::json;
using test::config_error_of;

json policy_doc() {
  return json::parse(R"({
    "version": 1,
    "mode": "ratio",
    "home_faction": 2,
    "terms": [
      { "param": "weight", "weight": 1.0, "scale": 200 },
      { "param": "speed_mps", "weight": 0.5, "scale": 5, "invert": true },
      { "param": "facing", "weight": 1.0, "scale": 1 }
    ],
    "pair_rules": [
      { "name": "player_vs_heavy_npc", "a": { "character_type": "player" },
        "b": { "character_type": ["npc"], "weight_at_least": "heavy" }, "share_b": 0.8 },
      { "name": "enemy_giants", "a": { "kind": ["giant"], "faction": "enemy", "ranges": { "hp": { "min": 10 } } },
        "share_b": 0.25 }
    ]
  })");
}

TEST(ParamsPolicyJson, ReadsEveryField) {
  const PushPolicy p = push_policy_from_json(policy_doc());
  EXPECT_EQ(p.mode(), PushMode::ratio);
  EXPECT_EQ(p.home_faction(), 2u);
  ASSERT_EQ(p.terms().size(), 3u);
  EXPECT_EQ(p.terms()[0].input, TermInput::weight_kg);
  EXPECT_EQ(p.terms()[0].scale, 200.0);
  EXPECT_TRUE(p.terms()[1].invert);
  EXPECT_TRUE(p.has_pair_dependent_terms());
  ASSERT_EQ(p.rules().size(), 2u);
  EXPECT_EQ(p.rules()[0].b.weight_min_kg, weight_class_kg(WeightClass::heavy));
  EXPECT_EQ(p.rules()[0].b.character_types, category_bit(CharacterType::npc));
  EXPECT_EQ(p.rules()[1].a.kinds, category_bit(Kind::giant));
  EXPECT_EQ(p.rules()[1].a.relations, category_bit(FactionRelation::enemy));
  ASSERT_EQ(p.rules()[1].a.ranges.size(), 1u);
  EXPECT_EQ(p.rules()[1].a.ranges[0].param, Param::hp);
  EXPECT_EQ(p.rules()[1].a.ranges[0].min, 10.0);
  EXPECT_EQ(p.rules()[1].share_b, 0.25);
}

TEST(ParamsPolicyJson, ErrorsNameTheField) {
  struct Case {
    const char* what;
    json doc;
    std::string path;
    std::string part;
  };
  std::vector<Case> cases;
  auto with = [](auto edit) {
    json d = policy_doc();
    edit(d);
    return d;
  };
  cases.push_back({"unknown param", with([](json& d) { d["terms"][0]["param"] = "wieght"; }), "terms[0].param",
                   "unknown param name 'wieght'"});
  cases.push_back({"NaN weight", with([](json& d) { d["terms"][1]["weight"] = std::nan(""); }), "terms[1].weight",
                   "NaN"});
  cases.push_back({"zero scale", with([](json& d) { d["terms"][1]["scale"] = 0; }), "terms[1].scale", "out of range"});
  cases.push_back({"inf scale", with([](json& d) { d["terms"][1]["scale"] = std::numeric_limits<double>::infinity(); }),
                   "terms[1].scale", "infinite"});
  cases.push_back({"unknown mode", with([](json& d) { d["mode"] = "winner_takes_all"; }), "mode", "unknown mode"});
  cases.push_back({"missing mode", with([](json& d) { d.erase("mode"); }), "mode", "missing"});
  cases.push_back({"unknown category", with([](json& d) { d["pair_rules"][0]["b"]["weight_at_least"] = "hevy"; }),
                   "pair_rules[0].b.weight_at_least", "unknown category 'hevy'"});
  cases.push_back({"unknown character type",
                   with([](json& d) { d["pair_rules"][0]["b"]["character_type"] = json::array({"npc", "boss"}); }),
                   "pair_rules[0].b.character_type[1]", "unknown category 'boss'"});
  cases.push_back({"share out of range", with([](json& d) { d["pair_rules"][1]["share_b"] = -0.1; }),
                   "pair_rules[1].share_b", "out of range"});
  cases.push_back({"unknown range param",
                   with([](json& d) { d["pair_rules"][1]["a"]["ranges"]["hitpoints"] = {{"min", 1}}; }),
                   "pair_rules[1].a.ranges.hitpoints", "unknown parameter"});
  cases.push_back({"inverted range", with([](json& d) { d["pair_rules"][1]["a"]["ranges"]["hp"]["max"] = 5; }),
                   "pair_rules[1].a.ranges.hp.max", "below the minimum"});
  cases.push_back({"empty list", with([](json& d) { d["pair_rules"][1]["a"]["kind"] = json::array(); }),
                   "pair_rules[1].a.kind", "never matches"});
  cases.push_back({"home faction", with([](json& d) { d["home_faction"] = 0; }), "home_faction", "out of range"});
  cases.push_back({"typo key", with([](json& d) { d["terms"][0]["scael"] = 3; }), "terms[0].scael", "unknown key"});
  cases.push_back({"wrong type", with([](json& d) { d["terms"][0]["invert"] = "yes"; }), "terms[0].invert",
                   "expected true or false"});
  cases.push_back({"duplicate rule", with([](json& d) { d["pair_rules"][1]["name"] = "player_vs_heavy_npc"; }),
                   "pair_rules[1].name", "duplicate"});
  for (const Case& c : cases) {
    const ConfigError e = config_error_of([&] { (void)push_policy_from_json(c.doc); });
    EXPECT_EQ(e.path(), c.path) << c.what << ": " << e.what();
    EXPECT_NE(e.message().find(c.part), std::string::npos) << c.what << ": " << e.what();
  }
}

TEST(ParamsPolicyJson, MalformedJson) {
  const ConfigError e = config_error_of([] { (void)parse_push_policy("{\"mode\": \"ratio\",, }", "policy.json"); });
  EXPECT_EQ(e.path(), "");
  EXPECT_NE(e.message().find("policy.json: malformed JSON"), std::string::npos) << e.what();
}

// A number beyond double's range (nlohmann: out_of_range, not parse_error) is malformed JSON too:
// the server's operator channel hands parse_push_policy whatever a peer sent (found by fuzzing).
TEST(ParamsPolicyJson, OverflowingNumberIsMalformedJson) {
  const ConfigError e = config_error_of([] { (void)parse_push_policy(R"({"mode": "ratio", "x": -1e999})", "policy_json"); });
  EXPECT_EQ(e.path(), "");
  EXPECT_NE(e.message().find("policy_json: malformed JSON"), std::string::npos) << e.what();
}

}  // namespace
}  // namespace throng::params
