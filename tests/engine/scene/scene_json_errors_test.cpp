// The loader rejects each class of bad input and names the field (JSON path) in the error.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "throng/scene/build_scene.h"
#include "throng/scene/scene_error.h"
#include "throng/scene/scene_json.h"

namespace throng::scene {
namespace {

// A small valid scene that each test breaks in one place.
nlohmann::json valid_scene() {
  return nlohmann::json::parse(R"({
    "name": "t", "ticks": 10,
    "scenery": [ { "type": "box", "archetype": "wall", "centre": [0, 5, 1], "half_extents_m": [10, 0.5, 1] },
                 { "type": "cylinder", "archetype": "bush", "centre": [3, 0, 0.5], "radius_m": 1, "half_height_m": 0.5,
                   "params": { "softness": 0.5 } } ],
    "spawns": [ { "count": 3, "shape": { "type": "disk", "centre": [0, 0], "radius_m": 2 } },
                { "count": 2, "shape": { "type": "line", "from": [0, 0], "to": [4, 0] },
                  "behaviour": { "type": "seek_point", "target": [0, 0], "speed_mps": 1 } },
                { "count": 4, "shape": { "type": "rect", "centre": [0, -3], "half_extents_m": [2, 1] },
                  "behaviour": { "type": "march", "direction": [1, 0], "speed_mps": 1 } } ]
  })");
}

// Expects scene_from_json(doc) to throw with exactly this path and a message containing `what`.
void expect_error(const nlohmann::json& doc, const std::string& path, const std::string& what) {
  try {
    (void)scene_from_json(doc);
    FAIL() << "no error for " << path;
  } catch (const SceneError& e) {
    EXPECT_EQ(e.path(), path) << e.what();
    EXPECT_NE(e.message().find(what), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << "message must start with the path: " << e.what();
  }
}

TEST(SceneJsonErrors, ValidSceneLoads) {
  const SceneDef s = scene_from_json(valid_scene());
  EXPECT_EQ(s.agent_count(), 9u);
  EXPECT_EQ(s.scenery.size(), 2u);
  EXPECT_EQ(s.scenery[1].params.at("softness"), 0.5);
}

TEST(SceneJsonErrors, NegativeCount) {
  auto doc = valid_scene();
  doc["spawns"][2]["count"] = -1;
  expect_error(doc, "spawns[2].count", "must be >= 0");
}

TEST(SceneJsonErrors, FractionalCountAndMissingCount) {
  auto doc = valid_scene();
  doc["spawns"][0]["count"] = 2.5;
  expect_error(doc, "spawns[0].count", "whole number");
  doc["spawns"][0].erase("count");
  expect_error(doc, "spawns[0].count", "is required");
}

TEST(SceneJsonErrors, NanAndInfinityRejected) {
  auto doc = valid_scene();  // JSON text cannot hold NaN, but an inline object built in code can
  doc["spawns"][0]["shape"]["radius_m"] = std::nan("");
  expect_error(doc, "spawns[0].shape.radius_m", "finite");
  doc = valid_scene();
  doc["scenery"][0]["centre"][1] = std::numeric_limits<double>::infinity();
  expect_error(doc, "scenery[0].centre[1]", "finite");
  doc = valid_scene();
  doc["settings"] = {{"dt_s", std::numeric_limits<double>::quiet_NaN()}};
  expect_error(doc, "settings.dt_s", "finite");
}

TEST(SceneJsonErrors, NegativeSizes) {
  auto doc = valid_scene();
  doc["scenery"][0]["half_extents_m"][1] = -0.5;
  expect_error(doc, "scenery[0].half_extents_m[1]", "must be > 0");
  doc = valid_scene();
  doc["scenery"][1]["radius_m"] = -1;
  expect_error(doc, "scenery[1].radius_m", "must be > 0");
  doc = valid_scene();
  doc["spawns"][1]["radius_m"] = 0;
  expect_error(doc, "spawns[1].radius_m", "must be > 0");
  doc = valid_scene();
  doc["spawns"][0]["half_height_m"] = -0.1;
  expect_error(doc, "spawns[0].half_height_m", "must be >= 0");
  doc = valid_scene();
  doc["spawns"][2]["shape"]["half_extents_m"][0] = -2;
  expect_error(doc, "spawns[2].shape.half_extents_m[0]", "must be >= 0");
}

TEST(SceneJsonErrors, UnknownKeys) {
  auto doc = valid_scene();
  doc["spawns"][1]["radius"] = 0.3;  // typo for radius_m
  expect_error(doc, "spawns[1].radius", "unknown key");
  doc = valid_scene();
  doc["scenery"][0]["radius_m"] = 1.0;  // belongs to cylinders, not boxes
  expect_error(doc, "scenery[0].radius_m", "unknown key");
  doc = valid_scene();
  doc["tick"] = 5;
  expect_error(doc, "tick", "unknown key");
  doc = valid_scene();
  doc["settings"] = {{"iteration", 4}};
  expect_error(doc, "settings.iteration", "unknown key");
}

TEST(SceneJsonErrors, UnknownKindsAndWrongTypes) {
  auto doc = valid_scene();
  doc["spawns"][0]["shape"]["type"] = "circle";
  expect_error(doc, "spawns[0].shape.type", "unknown type 'circle'");
  doc = valid_scene();
  doc["scenery"][1]["type"] = "sphere";
  expect_error(doc, "scenery[1].type", "unknown type 'sphere'");
  doc = valid_scene();
  doc["spawns"][1]["behaviour"]["type"] = "wander";
  expect_error(doc, "spawns[1].behaviour.type", "unknown type 'wander'");
  doc = valid_scene();
  doc["spawns"][0]["grounded"] = "yes";
  expect_error(doc, "spawns[0].grounded", "true or false");
  doc = valid_scene();
  doc["spawns"][0]["shape"]["centre"] = {1, 2, 3};
  expect_error(doc, "spawns[0].shape.centre", "array of 2 numbers");
  doc = valid_scene();
  doc["spawns"] = {{"count", 1}};
  expect_error(doc, "spawns", "must be an array");
  doc = valid_scene();
  doc["scale_scenery"] = 0;
  expect_error(doc, "scale_scenery", "true or false");
}

TEST(SceneJsonErrors, SettingsOutOfRange) {
  auto doc = valid_scene();
  doc["settings"] = {{"iterations", 0}};
  expect_error(doc, "settings.iterations", "must be >= 1");
  doc["settings"] = {{"dt_s", 2.0}};
  expect_error(doc, "settings.dt_s", "must be <= 1");
}

TEST(SceneJsonErrors, BehaviourProblems) {
  auto doc = valid_scene();
  doc["spawns"][2]["behaviour"]["target"] = {1, 1};  // both direction and target
  expect_error(doc, "spawns[2].behaviour", "exactly one");
  doc = valid_scene();
  doc["spawns"][2]["behaviour"]["direction"] = {0, 0};
  expect_error(doc, "spawns[2].behaviour.direction", "must not be zero");
  doc = valid_scene();
  doc["spawns"][1]["behaviour"]["speed_mps"] = -1;
  expect_error(doc, "spawns[1].behaviour.speed_mps", "must be >= 0");
}

TEST(SceneJsonErrors, MeshIndicesChecked) {
  auto doc = valid_scene();
  doc["scenery"].push_back({{"type", "mesh"}, {"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {"triangles", {{0, 1, 3}}}});
  expect_error(doc, "scenery[2].triangles[0][2]", "vertex index");
}

TEST(SceneJsonErrors, MalformedFileNamesTheFile) {
  try {
    (void)load_scene_file("/nonexistent/scene.json");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.json"), std::string::npos);
  }
}

// Expects build_scene to throw with exactly this path and a message containing `what`.
void expect_build_error(const nlohmann::json& doc, const std::string& path, const std::string& what) {
  const SceneDef s = scene_from_json(doc);  // the file itself is fine...
  try {
    (void)build_scene(s);                   // ...the names are checked against the table here
    FAIL() << "no error for " << path;
  } catch (const SceneError& e) {
    EXPECT_EQ(e.path(), path) << e.what();
    EXPECT_NE(e.message().find(what), std::string::npos) << e.what();
  }
}

// Archetype and parameter names are checked when the World is built (the table is known then).
TEST(SceneJsonErrors, UnknownArchetypeNamedAtBuild) {
  auto doc = valid_scene();
  doc["spawns"][1]["archetype"] = "dragon";
  expect_build_error(doc, "spawns[1].archetype", "unknown archetype 'dragon' (known: bush, cavalry, cushion,");
  doc = valid_scene();
  doc["scenery"][0]["archetype"] = "glass";
  expect_build_error(doc, "scenery[0].archetype", "unknown archetype 'glass'");
}

TEST(SceneJsonErrors, UnknownOrBadParameterNamedAtBuild) {
  auto doc = valid_scene();
  doc["scenery"][1]["params"] = {{"softnes", 0.5}};
  expect_build_error(doc, "scenery[1].params.softnes", "unknown parameter");
  doc = valid_scene();
  doc["scenery"][1]["params"] = {{"softness", 1.5}};
  expect_build_error(doc, "scenery[1].params.softness", "");
  doc = valid_scene();
  doc["spawns"][0]["faction"] = 300;  // parameter range 0..255, checked at load
  expect_error(doc, "spawns[0].faction", "must be <= 255");
}

TEST(SceneJsonErrors, BadInlinePolicyNamedUnderPolicy) {
  auto doc = valid_scene();
  doc["policy"] = {{"mode", "telepathy"}};
  expect_build_error(doc, "policy.mode", "");
  doc = valid_scene();
  doc["params"] = "/nonexistent/params.json";
  expect_build_error(doc, "params", "/nonexistent/params.json");
}

// A SceneDef made in code can carry inline text that is not JSON (a file's inline object is always
// valid text): the build names the field instead of letting the JSON library's exception escape.
TEST(SceneJsonErrors, InlineTextThatIsNotJsonNamedAtBuild) {
  SceneDef s = scene_from_json(valid_scene());
  s.params.file.clear();
  s.params.inline_json = R"({"archetypes": )";
  try {
    (void)build_scene(s);
    FAIL() << "no error for truncated inline params";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.path(), "params") << e.what();
    EXPECT_NE(e.message().find("inline document"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace throng::scene
