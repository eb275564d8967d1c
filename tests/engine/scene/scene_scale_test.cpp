// --agents scaling: exact total, proportional groups, density kept.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"
#include "throng/scene/scene_error.h"
#include "throng/scene/spawn.h"

namespace throng::scene {
namespace {

TEST(SceneScale, CountsAddUpAndKeepRatios) {
  EXPECT_EQ(proportional_counts({1, 1, 1}, 10), (std::vector<std::uint32_t>{4, 3, 3}));  // ties to the lower index
  EXPECT_EQ(proportional_counts({5000, 3000, 1500, 500}, 1000), (std::vector<std::uint32_t>{500, 300, 150, 50}));
  EXPECT_EQ(proportional_counts({0, 7}, 3), (std::vector<std::uint32_t>{0, 3}));
  for (const auto& name : builtin_scene_names()) {
    for (const std::uint64_t n : {1ull, 777ull, 100'000ull}) EXPECT_EQ(scale_scene(builtin_scene(name), n).agent_count(), n) << name;
  }
}

TEST(SceneScale, DensityIsKept) {
  // Bodies per m^2 of every area-shaped group stays the same, up to count rounding.
  for (const auto& name : {"crush", "street", "obstacles", "mixed", "battle"}) {
    const SceneDef base = builtin_scene(name);
    for (const std::uint64_t n : {500ull, 50'000ull}) {
      const SceneDef scaled = scale_scene(base, n);
      for (std::size_t i = 0; i < base.spawns.size(); ++i) {
        const double a0 = shape_area(base.spawns[i].shape), a1 = shape_area(scaled.spawns[i].shape);
        if (a0 == 0.0) continue;
        const double d0 = base.spawns[i].count / a0, d1 = scaled.spawns[i].count / a1;
        EXPECT_NEAR(d1 / d0, 1.0, 1.0 / scaled.spawns[i].count + 1e-12) << name << " group " << i << " N=" << n;
      }
    }
  }
}

TEST(SceneScale, CrushDiskFollowsHalfSqrtN) {
  // The crush definition: radius 0.5 * sqrt(N) at any N.
  for (const std::uint64_t n : {1'000ull, 20'000ull, 100'000ull}) {
    const SceneDef s = scale_scene(builtin_scene("crush"), n);
    EXPECT_NEAR(s.spawns[0].shape.radius_m, 0.5 * std::sqrt(double(n)), 1e-9) << n;
  }
}

TEST(SceneScale, LayoutScalesButBodiesDoNot) {
  const SceneDef base = builtin_scene("street");
  const SceneDef big = scale_scene(base, base.agent_count() * 4);  // s = 2
  EXPECT_DOUBLE_EQ(big.scenery[0].centre.y, 2.0 * base.scenery[0].centre.y);
  EXPECT_DOUBLE_EQ(big.scenery[0].half_extents_m.x, 2.0 * base.scenery[0].half_extents_m.x);
  EXPECT_EQ(big.scenery[0].centre.z, base.scenery[0].centre.z);
  EXPECT_EQ(big.spawns[0].radius_m, base.spawns[0].radius_m);
  EXPECT_EQ(big.spawns[0].behavior.speed_mps, base.spawns[0].behavior.speed_mps);
  // Shrinking never makes walls paper-thin.
  const SceneDef small = scale_scene(base, base.agent_count() / 100);
  EXPECT_GE(small.scenery[0].half_extents_m.y, std::min(base.scenery[0].half_extents_m.y, kMinScaledScenery_m));
}

// crush_post and crush_pillars say "scale_scenery": false: at any N the post is the 0.5 m one at
// the goal and the pillars stand 3 m out, where the jam meets them; only the crowd scales.
TEST(SceneScale, ScenerySaidToStayIsNotScaled) {
  for (const char* file : {"crush_post.json", "crush_pillars.json"}) {
    const SceneDef base = load_scene(std::string(THRONG_SOURCE_DIR) + "/server/engine/data/scenes/" + file);
    ASSERT_FALSE(base.scale_scenery) << file;
    const SceneDef small = scale_scene(base, base.agent_count() / 4);  // s = 1/2
    EXPECT_EQ(small.scenery, base.scenery) << file;
    EXPECT_EQ(small.scenery[0].radius_m, 0.5) << file;
    EXPECT_DOUBLE_EQ(small.spawns[0].shape.radius_m, 0.5 * base.spawns[0].shape.radius_m) << file;
    EXPECT_EQ(small.agent_count(), base.agent_count() / 4) << file;
  }
  // The same scene with the default scales its scenery with the crowd.
  SceneDef map = load_scene(std::string(THRONG_SOURCE_DIR) + "/server/engine/data/scenes/crush_post.json");
  map.scale_scenery = true;
  EXPECT_EQ(scale_scene(map, map.agent_count() / 4).scenery[0].radius_m, 0.25);
}

TEST(SceneScale, LineKeepsItsSpacing) {
  SceneDef s;
  SpawnGroup g;
  g.count = 10;
  g.shape.kind = SpawnAreaKind::line;
  g.shape.from = {0.0, 0.0};
  g.shape.to = {10.0, 0.0};
  s.spawns.push_back(g);
  const SceneDef big = scale_scene(s, 40);  // s = 2: 4x the bodies on a 4x longer line
  const auto& sh = big.spawns[0].shape;
  EXPECT_DOUBLE_EQ(sh.to.x - sh.from.x, 40.0);
  EXPECT_DOUBLE_EQ(0.5 * (sh.to.x + sh.from.x), 10.0);  // midpoint 5 scaled by 2
}

TEST(SceneScale, RejectsZeroAndEmpty) {
  EXPECT_THROW((void)scale_scene(builtin_scene("crush"), 0), SceneError);
  EXPECT_THROW((void)scale_scene(SceneDef{}, 10), SceneError);
}

}  // namespace
}  // namespace throng::scene
