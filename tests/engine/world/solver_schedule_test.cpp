// The solver sweeps a dense crowd in dependency-level order (solver/pair_schedule.h: SSE2 lanes,
// 4,096-pair bands) and a sparse one in the pairs' own order, choosing by a speed hint that is not
// part of the saved state. Both orders must give the same bits. A world restored from a checkpoint
// starts without the hint, so its first tick runs in plain order while the original, already
// scheduled, runs in level order: their hashes must agree on that tick and every one after.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "throng/scene/build_scene.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"
#include "throng/world/world.h"

namespace throng {
namespace {

void run(scene::BuiltScene& b, int ticks) {
  for (int t = 0; t < ticks; ++t) {
    b.driver.apply(b.world);
    b.world.step();
  }
}

// `agents` bodies, run into the packed phase (`ticks`), restored into a fresh copy, then both
// stepped on: the restored one's first sweep order differs, its bits must not.
void expect_orders_agree(const std::string& name, std::uint64_t agents, int ticks) {
  const scene::SceneDef def = scene::scale_scene(scene::builtin_scene(name), agents);
  scene::BuiltScene a = scene::build_scene(def);
  run(a, ticks);
  std::vector<std::uint8_t> saved;
  a.world.save_state(saved);
  scene::BuiltScene b = scene::build_scene(def);
  b.world.restore_state(saved);
  for (int t = 0; t < 3; ++t) {
    a.driver.apply(a.world);
    b.driver.apply(b.world);
    const StepStats sa = a.world.step();
    b.world.step();
    // The case under test: contact-heavy ticks that use the whole budget (no early exit), with
    // more pairs than one 4,096-pair band.
    ASSERT_EQ(sa.iterations_used, def.settings.iterations) << name;
    ASSERT_GT(sa.candidate_pairs, 4096u) << name;
    ASSERT_EQ(a.world.state_hash(), b.world.state_hash()) << name << ", tick " << a.world.tick();
  }
}

TEST(SolverSchedule, LevelOrderGivesTheBitsOfThePairOrderOnCrush) { expect_orders_agree("crush", 6000, 150); }

// Mixed radii and weights: unequal shares, conflict shares, bodies on several grid levels.
TEST(SolverSchedule, LevelOrderGivesTheBitsOfThePairOrderOnMixed) { expect_orders_agree("mixed", 5000, 150); }

}  // namespace
}  // namespace throng
