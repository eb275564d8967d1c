// The NPC AI's tick allocates nothing once it has run once, even while the battle spreads out:
// its grid covers the bodies' extent, which grows as routed troops flee, and its per-cell arrays
// are made at the largest grid's size on the first tick (NpcAi::size_grid_for_max_cells). Sized to
// each tick's grid instead, they reallocated in the tick (and the server's resident memory grew
// with them) for the first quarter of an hour of the default battle.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "npc_ai.h"
#include "support/counting_new.h"  // counts operator new while g_counting is set
#include "throng/scene/build_scene.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"

namespace throng::match {
namespace {

TEST(NpcAiNoAllocation, ASpreadingBattleRebuildsItsGridWithoutAllocating) {
  scene::BuiltScene b = scene::build_scene(scene::scale_scene(scene::builtin_scene("battle"), 600));
  World& w = b.world;
  NpcAi ai{NpcAiSettings{}};
  ai.init(w);
  const std::size_t n = w.body_count();
  std::vector<std::uint32_t> controlled(n, 0);
  std::vector<float> yaw(n, 0.0f);
  ai.update(w, controlled, yaw);  // warm-up: the one tick that may allocate
  // The counter itself works.
  g_counting = true;
  { std::vector<int> probe(16); EXPECT_EQ(probe.size(), 16u); }
  g_counting = false;
  ASSERT_GE(g_allocations.load(), 1u);
  // The battle spreads to 2, 10 and 60 times its extent (the last past the grid's cell cap, so
  // its cells coarsen): every tick's grid is larger than any before it.
  for (const double spread : {2.0, 10.0, 60.0}) {
    for (std::size_t d = 0; d < n; ++d) {
      const ObjectId id = w.id_at(d);
      const Vec3 p = w.position(id);
      w.set_position(id, {p.x * spread, p.y * spread, p.z});
    }
    g_allocations = 0;
    g_counting = true;
    ai.update(w, controlled, yaw);
    g_counting = false;
    EXPECT_EQ(g_allocations.load(), 0u) << "spread " << spread;
    for (std::size_t d = 0; d < n; ++d) {
      const ObjectId id = w.id_at(d);
      const Vec3 p = w.position(id);
      w.set_position(id, {p.x / spread, p.y / spread, p.z});
    }
  }
}

}  // namespace
}  // namespace throng::match
