// World::set_push_events_recorded: a re-simulation that reads no push events turns them off. The
// state must not depend on it, and the events must say so (none while off, this tick's once on).
#include <gtest/gtest.h>

#include <string>

#include "throng/scene/build_scene.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"

namespace throng {
namespace {

TEST(PushEventSwitch, TurningEventsOffChangesNoStateAndEmptiesThem) {
  // Scenery (the general pairs and their planes) and unequal weights (held pairs), in ticks that
  // solve once and ticks that solve twice.
  for (const std::string name : {"mixed", "street"}) {
    scene::SceneDef def = scene::scale_scene(scene::load_scene(name), 2000);
    scene::BuiltScene on = scene::build_scene(def);
    scene::BuiltScene off = scene::build_scene(def);
    off.world.set_push_events_recorded(false);
    int second_searches = 0;
    std::size_t events_on = 0;
    for (int t = 1; t <= 90; ++t) {
      if (t == 60) off.world.set_push_events_recorded(true);
      on.driver.apply(on.world);
      second_searches += static_cast<int>(on.world.step().second_search);
      events_on += on.world.push_events().size();
      off.driver.apply(off.world);
      off.world.step();
      ASSERT_EQ(on.world.state_hash(), off.world.state_hash()) << name << " tick " << t;
      if (t < 60) {
        ASSERT_TRUE(off.world.push_events().empty()) << name << " tick " << t;
        continue;
      }
      // Back on: the very events of a world that always recorded them.
      const auto a = on.world.push_events(), b = off.world.push_events();
      ASSERT_EQ(a.size(), b.size()) << name << " tick " << t;
      for (std::size_t k = 0; k < a.size(); ++k) {
        ASSERT_TRUE(a[k].a == b[k].a && a[k].b == b[k].b && a[k].depth_m == b[k].depth_m &&
                    a[k].share_a == b[k].share_a && a[k].push_m == b[k].push_m)
            << name << " tick " << t << " event " << k;
      }
    }
    EXPECT_GT(events_on, 0u) << name << ": the scene must push for this test to mean anything";
    // mixed's charging riders move bodies past the margin: ticks that search and solve twice.
    if (name == "mixed") {
      EXPECT_GT(second_searches, 0);
    }
    // Off again: this tick's events are gone at once, not left from the last recorded tick.
    off.world.set_push_events_recorded(false);
    EXPECT_TRUE(off.world.push_events().empty()) << name;
  }
}

}  // namespace
}  // namespace throng
