// A packed crowd's pressure carried from tick to tick (solver/fast_pair_kernel.h): in a crowd that
// keeps pressing on one point, the pushes between neighbours grow towards the middle, like pressure
// in a fluid. The fast pairs' warm start carries them whole along fixed normals
// (kFastWarmStartCapOverRadius), so a few sweeps a tick keep the core apart. Cut at half a radius,
// as the general pairs' warm start is, the core had to be rebuilt every tick and stayed several
// times deeper (figures: docs/design/solver.md).
#include <gtest/gtest.h>

#include <algorithm>

#include "throng/scene/build_scene.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/residual.h"
#include "throng/scene/scale.h"

namespace throng {
namespace {

TEST(CrowdPressure, CrushCoreStaysApartWithFewSweeps) {
  scene::SceneDef def = scene::scale_scene(scene::builtin_scene("crush"), 3000);
  def.settings.iterations = 6;
  scene::BuiltScene b = scene::build_scene(def);
  float largest_push = 0.0f;
  for (int t = 0; t < 300; ++t) {
    b.driver.apply(b.world);
    b.world.step();
  }
  for (const PushEvent& e : b.world.push_events()) largest_push = std::max(largest_push, e.push_m);
  const scene::ResidualStats r = scene::measure_residual(b.world);
  EXPECT_EQ(r.nan_count, 0u);
  EXPECT_GT(largest_push, 2.0f * 0.35f);  // the core really is under pressure (pushes of radii)
  EXPECT_LT(r.max_pen_over_radius, 0.2);
  EXPECT_LT(r.p99_pen_over_radius, 0.08);
}

}  // namespace
}  // namespace throng
