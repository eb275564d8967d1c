#include "throng/params/param_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "params_test_util.h"
#include "throng/params/params_json.h"

namespace throng::params {
namespace {

using nlohmann::json;
using test::config_error_of;

json layered_doc() {
  return json::parse(R"({
    "version": 1,
    "defaults": { "importance": 2, "weight": "light", "hp": 90 },
    "groups": [ { "id": 4, "morale": 5, "member_count": 30, "strength": 2, "importance": 1 } ],
    "archetypes": {
      "cavalry": { "kind": "mount", "weight": "very_heavy", "size_m": 1.2 },
      "bush": { "kind": "scenery", "fixed": true, "softness": 0.5, "facing": [0, 2] }
    },
    "objects": [
      { "object_id": 7, "params": { "importance": 9, "group_id": 4 } },
      { "object_id": 7, "collision_id": 1, "params": { "weight_kg": 300 } }
    ]
  })");
}

TEST(ParamsTable, LayersApplyInOrder) {
  const ParamTable t = param_table_from_json(layered_doc());
  EXPECT_EQ(t.defaults().importance, 2.0);
  EXPECT_EQ(t.defaults().weight_kg, weight_class_kg(WeightClass::light));

  const ObjectParams& cav = t.archetype("cavalry");
  EXPECT_EQ(cav.kind, Kind::mount);
  EXPECT_EQ(cav.weight_kg, weight_class_kg(WeightClass::very_heavy));
  EXPECT_EQ(cav.hp, 90.0);  // inherited from defaults
  EXPECT_EQ(cav.importance, 2.0);

  const ObjectParams body0 = t.resolve("cavalry", 7, 0);
  EXPECT_EQ(body0.object_id, 7u);
  EXPECT_EQ(body0.collision_id, 0u);
  EXPECT_EQ(body0.importance, 9.0);  // object-wide override
  EXPECT_EQ(body0.group_id, 4u);
  EXPECT_EQ(body0.weight_kg, weight_class_kg(WeightClass::very_heavy));

  const ObjectParams body1 = t.resolve("cavalry", 7, 1);
  EXPECT_EQ(body1.importance, 9.0);
  EXPECT_EQ(body1.weight_kg, 300.0);  // collision-specific override on top

  const ObjectParams other = t.resolve("", 8, 0);
  EXPECT_EQ(other.importance, t.defaults().importance);

  const ObjectParams& bush = t.archetype("bush");
  EXPECT_TRUE(bush.fixed);
  EXPECT_EQ(bush.softness, 0.5);
  EXPECT_NEAR(bush.facing_x, 0.0, 1e-15);
  EXPECT_NEAR(bush.facing_y, 1.0, 1e-15);

  EXPECT_EQ(t.archetype_names(), (std::vector<std::string>{"bush", "cavalry"}));
  ASSERT_TRUE(t.groups().contains(4));
  EXPECT_EQ(t.groups().at(4).member_count, 30u);
  EXPECT_EQ(t.groups().morale(4), 5.0);
  EXPECT_THROW((void)t.archetype("dragon"), std::invalid_argument);
}

struct BadDoc {
  const char* what;
  json doc;
  std::string path;
  std::string message_part;
};

TEST(ParamsTable, JsonErrorsNameTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<BadDoc> cases;
  {
    json d = layered_doc();
    d["archetypes"]["cavalry"]["weight"] = "hevy";
    cases.push_back({"unknown category", d, "archetypes.cavalry.weight", "unknown category 'hevy'"});
  }
  {
    json d = layered_doc();
    d["defaults"]["importance"] = nan;
    cases.push_back({"NaN", d, "defaults.importance", "NaN"});
  }
  {
    json d = layered_doc();
    d["archetypes"]["bush"]["softness"] = 1.5;
    cases.push_back({"out of range", d, "archetypes.bush.softness", "out of range"});
  }
  {
    json d = layered_doc();
    d["archetypes"]["cavalry"]["wieght"] = 3;
    cases.push_back({"unknown param name", d, "archetypes.cavalry.wieght", "unknown parameter"});
  }
  {
    json d = layered_doc();
    d["objects"][0]["params"]["group_id"] = 5;
    cases.push_back({"unknown group", d, "objects[0].params.group_id", "unknown group 5"});
  }
  {
    json d = layered_doc();
    d["groups"][0]["strength"] = -1;
    cases.push_back({"group out of range", d, "groups[0].strength", "out of range"});
  }
  {
    json d = layered_doc();
    d["morale"] = {{"low_enter", 0.5}, {"low_exit", 0.45}};
    cases.push_back({"unordered thresholds", d, "morale.low_exit", "greater than low_enter"});
  }
  {
    json d = layered_doc();
    d["objects"].push_back({{"object_id", 7}, {"params", json::object()}});
    cases.push_back({"duplicate override", d, "objects[2]", "duplicate override for object 7"});
  }
  {
    json d = layered_doc();
    d["archetype"] = json::object();
    cases.push_back({"unknown top-level key", d, "archetype", "unknown key"});
  }
  {
    json d = layered_doc();
    d["archetypes"]["cavalry"]["kind"] = 2;
    cases.push_back({"category given as number", d, "archetypes.cavalry.kind", "expected one of"});
  }
  {
    json d = layered_doc();
    d["archetypes"]["cavalry"]["faction"] = 2.5;
    cases.push_back({"fractional id", d, "archetypes.cavalry.faction", "not a whole number"});
  }
  {
    json d = layered_doc();
    d["version"] = 2;
    cases.push_back({"future version", d, "version", "unsupported version"});
  }
  for (const BadDoc& c : cases) {
    const ConfigError e = config_error_of([&] { (void)param_table_from_json(c.doc); });
    EXPECT_EQ(e.path(), c.path) << c.what << ": " << e.what();
    EXPECT_NE(e.message().find(c.message_part), std::string::npos) << c.what << ": " << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(c.path + ": ", 0), 0u) << e.what();
  }
}

TEST(ParamsTable, TheBriefsExampleMessage) {
  json d = layered_doc();
  d["archetypes"]["cavalry"]["weight"] = "hevy";
  const ConfigError e = config_error_of([&] { (void)param_table_from_json(d); });
  EXPECT_EQ(std::string(e.what()).rfind("archetypes.cavalry.weight: unknown category 'hevy'", 0), 0u) << e.what();
}

TEST(ParamsTable, MalformedJsonNamesTheSource) {
  const ConfigError e = config_error_of([] { (void)parse_param_table("{ \"defaults\": ", "bad_params.json"); });
  EXPECT_EQ(e.path(), "");
  EXPECT_NE(e.message().find("bad_params.json"), std::string::npos) << e.what();
  EXPECT_NE(e.message().find("malformed JSON"), std::string::npos) << e.what();
  EXPECT_THROW((void)load_param_table("/nonexistent/params.json"), ConfigError);
}

// nlohmann reports a number too large for any JSON number type as out_of_range, not parse_error:
// it must still be the documented ConfigError (tests/fuzz params_json found a bare exception).
TEST(ParamsTable, OverflowingNumberIsMalformedJson) {
  const ConfigError e = config_error_of([] { (void)parse_param_table(R"({"version": 429E967295})", "big.json"); });
  EXPECT_EQ(e.path(), "");
  EXPECT_NE(e.message().find("big.json: malformed JSON"), std::string::npos) << e.what();
  EXPECT_NE(e.message().find("number overflow"), std::string::npos) << e.what();
}

TEST(ParamsTable, OverridesAreValidatedWhenAdded) {
  ParamTable t;
  ParamPatch bad;
  bad.values.emplace_back(Param::hp, -5.0);
  EXPECT_THROW(t.set_override(3, ParamTable::kAllCollisions, bad), std::invalid_argument);
  EXPECT_EQ(t.find_override(3, ParamTable::kAllCollisions), nullptr);
}

}  // namespace
}  // namespace throng::params
