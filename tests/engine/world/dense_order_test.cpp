// The world's dense order as callers see it: World::last_reorder publishes each re-sort a step
// makes, and World::dense_index finds a body without scanning.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "throng/scene/build_scene.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"
#include "world/world_fixtures.h"

namespace throng::test {
namespace {

// Bodies scattered in creation order (far from spatial order), walking, so the re-sort moves them.
World scattered_world(std::size_t n) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(-20.0, 20.0), vel(-1.5, 1.5);
  World w(WorldSettings{}, test_table(), weight_policy(params::PushMode::ratio, 50.0));
  for (std::size_t i = 0; i < n; ++i) {
    BodyDef d;
    d.position = {pos(rng), pos(rng), 0.35};
    const ObjectId id = w.create_body(d);
    w.set_desired_velocity(id, {vel(rng), vel(rng), 0.0});
  }
  return w;
}

std::vector<ObjectId> ids_in_dense_order(const World& w) {
  std::vector<ObjectId> ids(w.body_count());
  for (std::size_t d = 0; d < ids.size(); ++d) ids[d] = w.id_at(d);
  return ids;
}

TEST(DenseOrder, EveryStepPublishesTheReSortItMadeAndOnlyThat) {
  World w = scattered_world(400);
  std::size_t reorders = 0, changed = 0;
  for (int t = 0; t < 64; ++t) {
    const std::vector<ObjectId> before = ids_in_dense_order(w);
    w.step();
    const std::vector<ObjectId> after = ids_in_dense_order(w);
    const auto perm = w.last_reorder();
    if (perm.empty()) {
      EXPECT_EQ(after, before) << "tick " << w.tick() << ": the order changed without a published re-sort";
      continue;
    }
    ++reorders;
    ASSERT_EQ(perm.size(), before.size());
    std::vector<std::uint32_t> sorted(perm.begin(), perm.end());
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t k = 0; k < sorted.size(); ++k) ASSERT_EQ(sorted[k], k) << "not a permutation";
    // perm[new] = old: the body now at d was at perm[d].
    for (std::size_t d = 0; d < after.size(); ++d) ASSERT_EQ(after[d], before[perm[d]]) << "dense index " << d;
    changed += after != before ? 1 : 0;
  }
  // One per 16 ticks, except a period whose first two ticks both took part in a list's search.
  EXPECT_GE(reorders, 3u);
  EXPECT_LE(reorders, 4u);
  EXPECT_GE(changed, 1u);  // the scattered creation order is not the spatial order
}

// The re-sort keeps off the ticks that take part in a list's search ahead (the two together were
// the heaviest ticks): on a period's first tick when it surely does no search work, else on its
// second when that one surely does none, and never twice in a period. "Surely none": it keeps a list
// it kept the tick before, and neither begins a search, finishes the scan of one begun in three
// parts, nor takes the list of one (the first tick after a search in a tick of its own is not told
// apart from the tick that took a list searched ahead: world_step.cpp, reorder_due).
TEST(DenseOrder, ReSortsKeepOffTheTicksOfASearchAhead) {
  scene::BuiltScene b = scene::build_scene(scene::scale_scene(scene::builtin_scene("crush"), 3000));
  struct Seen {
    bool began = false, finished = false;  // began a search ahead; finished the scan of one begun in three parts
    bool takes = false;  // took the list of a search ahead (the tick after one begun in two, or finished)
    bool kept = false;   // kept a list (its own search or not)
    bool busy() const { return began || finished || takes; }
  };
  Seen before_last, last;  // the two ticks before this one
  std::vector<std::uint64_t> resorts;
  std::size_t deferred = 0, began_ticks = 0, finished_ticks = 0;
  for (int t = 0; t < 400; ++t) {
    b.driver.apply(b.world);
    const StepStats st = b.world.step();
    const std::uint64_t tick = b.world.tick();
    Seen now;
    now.began = st.pair_list_searched_ahead != 0;
    now.finished = st.pair_list_ahead_finished != 0;
    now.takes = (last.began && !now.finished) || last.finished;
    now.kept = st.pair_list_reused != 0 && st.second_search == 0;
    began_ticks += now.began ? 1 : 0;
    finished_ticks += now.finished ? 1 : 0;
    const bool sure_now = now.kept && last.kept && !now.busy();
    const bool sure_last = last.kept && before_last.kept && !last.busy();
    const bool resorted = !b.world.last_reorder().empty();
    SCOPED_TRACE(tick);
    if (tick % 16 == 0 && sure_now) {
      EXPECT_TRUE(resorted) << "a period's first tick without search work made no re-sort";
    }
    if (resorted) {
      EXPECT_LE(tick % 16, 1u);
      EXPECT_FALSE(now.began) << "re-sorted on a tick that began a search ahead";
      EXPECT_FALSE(now.finished) << "re-sorted on a tick that finished a search's scan";
      EXPECT_FALSE(now.takes) << "re-sorted on the tick that took a list searched ahead";
      if (!resorts.empty()) {
        EXPECT_NE(resorts.back() / 16, tick / 16) << "two re-sorts in a period";
      }
      if (tick % 16 == 1) {
        ++deferred;
        EXPECT_FALSE(sure_last) << "deferred from a first tick without search work";
      }
      resorts.push_back(tick);
    }
    before_last = last;
    last = now;
  }
  EXPECT_GT(began_ticks, 20u);  // a marching crowd: lists searched ahead all along
  EXPECT_GT(finished_ticks, began_ticks / 2);  // most of them in three parts
  EXPECT_GE(resorts.size(), 400u / 16 / 3);  // a period loses its re-sort only to a search's ticks
  EXPECT_GE(deferred, 1u);  // some period's first tick took part in a search and its second did not
}

// Steps until a step re-sorts (a period whose first two ticks both take part in a list's search has
// none), at most three periods.
bool step_until_resorted(World& w) {
  for (int t = 0; t < 48; ++t) {
    w.step();
    if (!w.last_reorder().empty()) return true;
  }
  return false;
}

TEST(DenseOrder, CreateDestroyAndRestoreEmptyTheReSort) {
  World w = scattered_world(100);
  ASSERT_TRUE(step_until_resorted(w));
  std::vector<std::uint8_t> saved;
  w.save_state(saved);
  BodyDef d;
  d.position = {50.0, 50.0, 0.35};
  const ObjectId extra = w.create_body(d);
  EXPECT_TRUE(w.last_reorder().empty());

  ASSERT_TRUE(step_until_resorted(w));
  w.destroy_body(extra);
  EXPECT_TRUE(w.last_reorder().empty());

  ASSERT_TRUE(step_until_resorted(w));
  World restored = scattered_world(100);
  ASSERT_TRUE(step_until_resorted(restored));
  restored.restore_state(saved);
  EXPECT_TRUE(restored.last_reorder().empty());
}

// A re-sort leaves the parameter records in the old order until a later tick settles them: reads,
// writes, checkpoints, creation and destruction in between must still find each body's own record.
TEST(DenseOrder, ParameterRecordsFollowTheirBodiesThroughEveryReSort) {
  World w = scattered_world(400);
  std::map<std::uint32_t, double> weight;  // by id value
  for (std::size_t d = 0; d < w.body_count(); ++d) {
    const ObjectId id = w.id_at(d);
    const double kg = 40.0 + static_cast<double>((d * 7) % 200);
    w.set_param(id, params::Param::weight_kg, kg);
    weight[id.value] = kg;
  }
  const auto expect_own_records = [&](const World& world, const std::string& when) {
    for (std::size_t d = 0; d < world.body_count(); ++d) {
      const ObjectId id = world.id_at(d);
      const params::ObjectParams& p = world.params(id);
      ASSERT_EQ(p.object_id, id.value) << when << ", dense index " << d;
      ASSERT_EQ(p.weight_kg, weight.at(id.value)) << when << ", dense index " << d;
    }
  };

  int re_sorts = 0;
  for (int t = 0; t < 200 && re_sorts < 3; ++t) {
    w.step();
    const std::string when = "after tick " + std::to_string(w.tick());
    expect_own_records(w, when);
    if (w.last_reorder().empty()) continue;
    ++re_sorts;
    if (re_sorts == 2) {
      // A write between the re-sort and the settling reaches the body's record (its push share
      // follows), and a checkpoint taken there restores the same records and the same ticks.
      const ObjectId heavy = w.id_at(5);
      w.set_param(heavy, params::Param::weight_kg, 900.0);
      weight[heavy.value] = 900.0;
      expect_own_records(w, when + ", after a write");
      std::vector<std::uint8_t> saved;
      w.save_state(saved);
      World twin = scattered_world(400);
      twin.restore_state(saved);
      expect_own_records(twin, when + ", restored");
      for (int k = 0; k < 40; ++k) {
        w.step();
        twin.step();
        ASSERT_EQ(twin.state_hash(), w.state_hash()) << "tick " << w.tick() << " after a restore between re-sort and settling";
        expect_own_records(twin, "restored twin at tick " + std::to_string(twin.tick()));
      }
    } else if (re_sorts == 3) {
      const ObjectId gone = w.id_at(3);
      w.destroy_body(gone);
      weight.erase(gone.value);
      expect_own_records(w, when + ", after a destroy");
      BodyDef def;
      def.position = {60.0, 60.0, 0.35};
      const ObjectId added = w.create_body(def);
      weight[added.value] = w.params(added).weight_kg;
      expect_own_records(w, when + ", after a create");
      for (int k = 0; k < 20; ++k) {
        w.step();
        expect_own_records(w, "tick " + std::to_string(w.tick()) + " after a create");
      }
    }
  }
  EXPECT_EQ(re_sorts, 3);
}

TEST(DenseOrder, DenseIndexFindsBodiesAndNothingElse) {
  World w = scattered_world(200);
  const ObjectId wall = w.add_fixed_box({0.0, 30.0, 1.0}, {1.0, 1.0, 1.0}, 0.0);
  for (int t = 0; t < 40; ++t) w.step();
  for (std::size_t d = 0; d < w.body_count(); ++d) {
    const auto found = w.dense_index(w.id_at(d));
    ASSERT_TRUE(found.has_value());
    EXPECT_EQ(*found, d);
  }
  EXPECT_FALSE(w.dense_index(wall).has_value());
  EXPECT_FALSE(w.dense_index(kNoObject).has_value());
  const ObjectId gone = w.id_at(5);
  w.destroy_body(gone);
  EXPECT_FALSE(w.dense_index(gone).has_value());
  // A stale id whose slot was reused names the new body only with the new generation.
  BodyDef d;
  d.position = {60.0, 60.0, 0.35};
  const ObjectId reused = w.create_body(d);
  EXPECT_FALSE(w.dense_index(gone).has_value());
  EXPECT_EQ(w.dense_index(reused), std::optional<std::size_t>(w.body_count() - 1));
}

}  // namespace
}  // namespace throng::test
