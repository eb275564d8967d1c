// The worst tick, not the last: a crowd converging on a small fixed post, every agent stepping its
// full speed into the jam (blocked_motion_carry 0), measured after every tick. Bodies round the post
// carry the crowd's pressure in their warm start; before each body's net warm-start move was cut
// (kWarmStartMoveCapOverRadius) that guess alone threw bodies a metre, onto bodies the pair search
// had seen apart, and single ticks showed two characters nearly on top of each other while the
// last tick looked fine (figures: docs/design/solver.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "throng/scene/build_scene.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/residual.h"
#include "throng/scene/scale.h"

namespace throng {
namespace {

struct Worst {
  double max_over_r = 0.0, p99_over_r = 0.0;
  int tick = 0;
};

Worst worst_tick(const std::string& scene_file, std::uint64_t agents, int ticks, int from) {
  scene::SceneDef def = scene::scale_scene(scene::load_scene(scene_file), agents);
  def.settings.blocked_motion_carry = 0.0;
  scene::BuiltScene b = scene::build_scene(def);
  Worst w;
  for (int t = 1; t <= ticks; ++t) {
    b.driver.apply(b.world);
    b.world.step();
    if (t < from) continue;
    const scene::ResidualStats r = scene::measure_residual(b.world);
    EXPECT_EQ(r.nan_count, 0u);
    if (r.max_pen_over_radius > w.max_over_r) w = {r.max_pen_over_radius, w.p99_over_r, t};
    w.p99_over_r = std::max(w.p99_over_r, r.p99_pen_over_radius);
  }
  return w;
}

TEST(WorstTick, CrowdOnAPostStaysApartInEveryTick) {
  const Worst w = worst_tick(std::string(THRONG_SOURCE_DIR) + "/server/engine/data/scenes/crush_post.json", 3000, 160, 61);
  std::printf("crush_post 3,000, carry 0: worst tick %d max %.3f r, worst p99 %.3f r\n", w.tick, w.max_over_r, w.p99_over_r);
  EXPECT_LT(w.max_over_r, 0.3);
  EXPECT_LT(w.p99_over_r, 0.05);
}

// The scene keeps its pillars as written at any N ("scale_scenery": false), so at 5,000 bodies the
// jams against them are a large share of the crowd. Eight sweeps left them at 0.30 r worst and
// 0.056 r p99 here; the sweeps the solve adds while a pair is deep (extra_iterations) bring them
// inside the bound.
TEST(WorstTick, CrowdAmongPillarsStaysApartInEveryTick) {
  const Worst w = worst_tick(std::string(THRONG_SOURCE_DIR) + "/server/engine/data/scenes/crush_pillars.json", 5000, 300, 61);
  std::printf("crush_pillars 5,000, carry 0: worst tick %d max %.3f r, worst p99 %.3f r\n", w.tick, w.max_over_r, w.p99_over_r);
  EXPECT_LT(w.max_over_r, 0.25);
  EXPECT_LT(w.p99_over_r, 0.05);
}

// Unequal weights (`mixed`: foot, riders and giants). Two causes made deep ticks here, each tested
// by this bound (figures: docs/design/solver.md):
// - a light body squeezed between two heavy ones that the jam presses together was pushed along its
//   pairs' normals until it landed deep in a body the tick's search had seen apart: the tick now
//   searches again when its solve moved a body further than the contact margin (World::step);
// - a heavy-light pair inside the jam carries a push of a radius or more from tick to tick; started
//   at the exact share every tick, the sweeps had to rebuild the heavy body's part of it each time:
//   such a pair now starts at the conflict share (held_by_neighbours). Without that, this crowd's
//   worst tick was 0.79 r and its worst p99 0.34 r.
TEST(WorstTick, MixedWeightsCrowdStaysApartInEveryTick) {
  const Worst w = worst_tick("mixed", 5000, 200, 61);
  std::printf("mixed 5,000, carry 0: worst tick %d max %.3f r, worst p99 %.3f r\n", w.tick, w.max_over_r, w.p99_over_r);
  EXPECT_LT(w.max_over_r, 0.25);
  EXPECT_LT(w.p99_over_r, 0.05);
}

}  // namespace
}  // namespace throng
