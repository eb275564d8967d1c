// The solver sweeps a dense crowd in dependency-level order with float displacements
// (solver/pair_schedule.h, fast_pair_kernel.h) and a small or calm one in the pairs' own order in
// double. The two give different bits, so the choice must be a function of the saved state alone
// (contact_solver.h: wants_schedule): a world restored from a checkpoint must take the same solve
// as the original on its first tick and every one after, and so give the same hashes.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "throng/scene/build_scene.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"
#include "throng/world/world.h"

#include "solver/pair_schedule.h"

namespace throng {
namespace {

void run(scene::BuiltScene& b, int ticks) {
  for (int t = 0; t < ticks; ++t) {
    b.driver.apply(b.world);
    b.world.step();
  }
}

// `agents` bodies, run into the packed phase (`ticks`), restored into a fresh copy, then both
// stepped on: the restored one has none of the original's scratch, its bits must still agree.
void expect_restored_agrees(const std::string& name, std::uint64_t agents, int ticks) {
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
    // The case under test: contact-heavy ticks that use the whole budget (no early exit; a deep
    // pair may add sweeps), with more pairs than one band, solved in bands.
    ASSERT_GE(sa.iterations_used, def.settings.iterations) << name;
    ASSERT_LE(sa.iterations_used, def.settings.iterations + def.settings.extra_iterations) << name;
    ASSERT_GT(sa.candidate_pairs, detail::kScheduleChunkPairs) << name;
    ASSERT_GT(sa.band_sweeps, 0u) << name;
    ASSERT_EQ(a.world.state_hash(), b.world.state_hash()) << name << ", tick " << a.world.tick();
  }
}

TEST(SolverSchedule, RestoredCrowdTakesTheSameSolveOnCrush) { expect_restored_agrees("crush", 6000, 150); }

// Mixed radii and weights: unequal shares, conflict shares, bodies on several grid levels.
TEST(SolverSchedule, RestoredCrowdTakesTheSameSolveOnMixed) { expect_restored_agrees("mixed", 5000, 150); }

}  // namespace
}  // namespace throng
