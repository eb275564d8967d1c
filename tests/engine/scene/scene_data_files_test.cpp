// The example scenes in server/engine/data/scenes load, build and run; files named like a built-in
// are its dump and must stay in sync with the code.
#include <gtest/gtest.h>

#include <filesystem>

#include "throng/scene/build_scene.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/residual.h"
#include "throng/scene/scale.h"
#include "throng/scene/scene_json.h"

namespace throng::scene {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> scene_files() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(fs::path(THRONG_SOURCE_DIR) / "server/engine/data/scenes"))
    if (e.path().extension() == ".json") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(SceneDataFiles, EveryExampleLoadsBuildsAndRuns) {
  const auto files = scene_files();
  ASSERT_FALSE(files.empty());
  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    const SceneDef s = load_scene_file(f.string());
    // Scaled down: this checks the file, not the solver's stamina.
    BuiltScene b = build_scene(s.agent_count() > 1000 ? scale_scene(s, 1000) : s);
    for (int t = 0; t < 5; ++t) step_scene(b);
    EXPECT_EQ(measure_residual(b.world).nan_count, 0u);
  }
}

TEST(SceneDataFiles, BuiltinDumpsMatchTheCode) {
  for (const auto& f : scene_files()) {
    const std::string name = f.stem().string();
    if (!is_builtin_scene(name)) continue;
    EXPECT_EQ(load_scene_file(f.string()), builtin_scene(name))
        << f << " is out of date; regenerate with: throng-bench --dump-scene " << name << " > " << f.string();
  }
}

}  // namespace
}  // namespace throng::scene
