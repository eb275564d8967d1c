// WorldSettings::threads changes no bit of the state: every built-in scene, scaled up far enough
// that its solve has several blocks per phase, steps to the same state hash every tick on 1, 2 and
// 4 threads; and a checkpoint moves between worlds of different thread counts.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "solver/pair_schedule.h"
#include "throng/scene/build_scene.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"

namespace throng {
namespace {

struct SceneRun {
  std::vector<std::uint64_t> hashes;
  std::uint32_t most_bands = 0;  // the most bands a tick's first sweep visited
};

SceneRun run_scene(const std::string& name, unsigned threads, std::uint64_t agents, int ticks) {
  scene::SceneDef def = scene::scale_scene(scene::load_scene(name), agents);
  def.settings.threads = threads;
  scene::BuiltScene b = scene::build_scene(def);
  SceneRun r;
  for (int t = 0; t < ticks; ++t) {
    b.driver.apply(b.world);
    const StepStats& s = b.world.step();
    if (s.iterations_used > 0) r.most_bands = std::max(r.most_bands, s.band_sweeps / s.iterations_used);
    r.hashes.push_back(b.world.state_hash());
  }
  return r;
}

TEST(ThreadedWorld, SameStateHashEveryTickOnEveryBuiltinScene) {
  std::uint32_t multi_block_scenes = 0;
  for (const std::string& name : scene::builtin_scene_names()) {
    const SceneRun one = run_scene(name, 1, 24000, 24);
    for (unsigned threads : {2u, 4u}) {
      const SceneRun many = run_scene(name, threads, 24000, 24);
      ASSERT_EQ(one.hashes.size(), many.hashes.size());
      for (std::size_t t = 0; t < one.hashes.size(); ++t) {
        ASSERT_EQ(one.hashes[t], many.hashes[t]) << name << ", " << threads << " threads, tick " << t + 1;
      }
    }
    // Three blocks or more: at least one phase with two blocks side by side.
    if (one.most_bands > 2 * detail::kBlockBands) ++multi_block_scenes;
    std::printf("%s: up to %u bands a sweep\n", name.c_str(), one.most_bands);
  }
  EXPECT_GE(multi_block_scenes, 4u);
}

TEST(ThreadedWorld, CheckpointMovesBetweenThreadCounts) {
  scene::SceneDef def = scene::scale_scene(scene::load_scene("crush"), 24000);
  def.settings.threads = 2;
  scene::BuiltScene two = scene::build_scene(def);
  for (int t = 0; t < 20; ++t) {
    two.driver.apply(two.world);
    two.world.step();
  }
  std::vector<std::uint8_t> bytes;
  two.world.save_state(bytes);
  def.settings.threads = 1;
  scene::BuiltScene one = scene::build_scene(def);
  one.world.restore_state(bytes);
  ASSERT_EQ(one.world.state_hash(), two.world.state_hash());
  // Both go on with the velocities the checkpoint holds.
  for (int t = 0; t < 10; ++t) {
    two.world.step();
    one.world.step();
    ASSERT_EQ(one.world.state_hash(), two.world.state_hash()) << "tick " << t + 1 << " after the restore";
  }
}

TEST(ThreadedWorld, SettingsRejectThreadCountsOutsideTheirRange) {
  WorldSettings s;
  s.threads = 0;
  EXPECT_THROW(s.validate(), std::invalid_argument);
  s.threads = 65;
  EXPECT_THROW(s.validate(), std::invalid_argument);
  s.threads = 64;
  EXPECT_NO_THROW(s.validate());
}

}  // namespace
}  // namespace throng
