// The pair list kept across ticks (server/engine/src/world/world_pair_list.cpp): a kept tick
// solves exactly the pairs a search with the contact margin finds; a tick that searches the list
// gives the bits a plain search gives; anything but motion drops the list; a restored world keeps
// the saved world's list and continues bit-identically; a crowd too fast for the skin stops
// searching lists for a while.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <utility>
#include <vector>

#include "throng/core/byte_io.h"
#include "throng/params/push_policy.h"
#include "throng/scene/build_scene.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"
#include "world/world_fixtures.h"
#include "world/world_impl.h"

namespace throng::detail {
struct WorldProbe {
  using Impl = World::Impl;
  static const Impl& impl(const World& w) { return *w.impl_; }
  static Impl& mut(World& w) { return *w.impl_; }
};
}  // namespace throng::detail

namespace throng {
namespace {

using detail::WorldProbe;
using Impl = WorldProbe::Impl;
using PairSet = std::set<std::pair<std::uint32_t, std::uint32_t>>;

scene::BuiltScene crowd(const char* name, std::uint64_t agents, double skin, std::uint32_t threads = 1) {
  scene::SceneDef def = scene::scale_scene(scene::builtin_scene(name), agents);
  def.settings.pair_list_skin_m = skin;
  def.settings.threads = threads;
  return scene::build_scene(def);
}

const StepStats& step(scene::BuiltScene& b) {
  b.driver.apply(b.world);
  return b.world.step();
}

// Every pair the grid's candidate test with the contact margin accepts at the solve's start
// positions (solver indices, lower first), by brute force over a sweep in x.
PairSet searched_pairs(const Impl& w) {
  const detail::SolverBodies& b = w.sb;
  const double margin = w.settings.contact_margin_m;
  const std::size_t n = b.size();
  std::vector<std::uint32_t> by_x(n);
  for (std::uint32_t i = 0; i < n; ++i) by_x[i] = i;
  std::sort(by_x.begin(), by_x.end(), [&](std::uint32_t p, std::uint32_t q) { return b.x[p] < b.x[q]; });
  const double max_r = *std::max_element(b.r.begin(), b.r.end());
  PairSet out;
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t i = by_x[k];
    for (std::size_t l = k + 1; l < n && b.x[by_x[l]] - b.x[i] < 2.0 * max_r + margin; ++l) {
      const std::uint32_t j = by_x[l];
      const double dx = b.x[j] - b.x[i], dy = b.y[j] - b.y[i];
      const double reach = b.r[i] + b.r[j] + margin;
      const double gap_z = std::fabs(b.z[j] - b.z[i]) - b.hh[i] - b.hh[j];
      const bool filter = (w.sgroup[i] & w.smask[j]) != 0 && (w.sgroup[j] & w.smask[i]) != 0;
      if (dx * dx + dy * dy < reach * reach && gap_z < reach && filter) out.insert({std::min(i, j), std::max(i, j)});
    }
  }
  return out;
}

// This tick's pairs (a, b, share): the kept list's taken entries, or the SolverPairs.
struct TickPair {
  std::uint32_t a, b;
  double share_a;
};
std::vector<TickPair> tick_pairs(const Impl& w) {
  std::vector<TickPair> out;
  if (w.pairs_in_list) {
    for (std::size_t k = 0; k < w.list.live; ++k) {
      const std::uint32_t e = w.list.of_pair[k];
      out.push_back({w.list.a[e], w.list.b[e], w.list.share[e]});
    }
  } else {
    for (const detail::SolverPair& p : w.pairs) out.push_back({p.a, p.b, p.share_a});
  }
  return out;
}

PairSet solved_pairs(const Impl& w) {
  PairSet out;
  for (const TickPair& p : tick_pairs(w)) out.insert({std::min(p.a, p.b), std::max(p.a, p.b)});
  return out;
}

TEST(PairList, KeptTicksSolveExactlyThePairsASearchFinds) {
  scene::BuiltScene b = crowd("crush", 3000, 0.2);
  const Impl& w = WorldProbe::impl(b.world);
  int kept = 0, compared = 0;
  for (int t = 0; t < 150; ++t) {
    const StepStats& st = step(b);
    if (st.pair_list_reused == 0) continue;
    ++kept;
    // A scheduled solve keeps the start positions in sb (an unscheduled one moves them), unless the
    // step ended by putting the next list's grid in place, which gathers sb afresh: it began a
    // search in two parts, or finished the scan of one in three (one begun in three leaves sb as
    // it is: the kept list still serves the next step).
    const bool two_part_begun = st.pair_list_searched_ahead != 0 && !w.list.ahead_begun;
    if (!w.sb.displaced || two_part_begun || st.pair_list_ahead_finished != 0) continue;
    ++compared;
    const PairSet solved = solved_pairs(w);
    ASSERT_EQ(solved.size(), tick_pairs(w).size()) << "a pair listed twice, tick " << st.tick;
    EXPECT_TRUE(w.pairs_in_list) << "a kept crowd tick copied its pairs out of the list";
    ASSERT_EQ(solved, searched_pairs(w)) << "tick " << st.tick;
  }
  EXPECT_GT(kept, 75);
  EXPECT_GT(compared, 50);
}

// The list is sorted as the fine grid's search lists its pairs, and its search tick takes the
// pushes from the cache, so a world that searches a list computes the plain search's bits (here
// the first tick, whose solve runs in the pairs' own order: no warm pushes yet). `mixed` has three
// radii, so pairs across grid levels too.
TEST(PairList, SearchTickGivesThePlainSearchsBits) {
  for (const char* name : {"crush", "mixed"}) {
    SCOPED_TRACE(name);
    scene::BuiltScene with = crowd(name, 3000, 0.2);
    scene::BuiltScene without = crowd(name, 3000, 0.0);
    const StepStats a = step(with);
    const StepStats b = step(without);
    // A tick that searched again after its solve (World::step) dropped the list it had searched.
    EXPECT_EQ(a.second_search, b.second_search);
    EXPECT_EQ(WorldProbe::impl(with.world).list.valid, a.second_search == 0);
    EXPECT_FALSE(WorldProbe::impl(without.world).list.valid);
    EXPECT_EQ(a.candidate_pairs, b.candidate_pairs);
    // (The state hashes differ: one world keeps a list, which is state.)
    auto bits = [](const World& w) {
      std::vector<double> v;
      for (std::size_t i = 0; i < w.body_count(); ++i) {
        v.insert(v.end(), {w.pos_x()[i], w.pos_y()[i], w.pos_z()[i]});
        const Vec3 vel = w.velocity(w.id_at(i));
        v.insert(v.end(), {vel.x, vel.y, vel.z});
      }
      return v;
    };
    const std::vector<double> bw = bits(with.world), bo = bits(without.world);
    ASSERT_EQ(bw.size(), bo.size());
    EXPECT_EQ(std::memcmp(bw.data(), bo.data(), bw.size() * sizeof(double)), 0);
    for (int t = 0; t < 30; ++t) EXPECT_EQ(step(without).pair_list_reused, 0u);
  }
}

// The schedule of a kept tick comes straight from the list's records (schedule_list_pairs), whose
// shares and warm-start caps are refreshed when a resistance changes; the general path builds it
// from SolverPairs (slot_fields). Both must fill every slot with the same bits, with warm pushes
// above the general cap (fast_warm_cap),
// on a kept tick right after weights changed under the list (its shares had gone stale).
TEST(PairList, ListAndPairSourcesFillTheSameSchedule) {
  WorldSettings settings;
  settings.iterations = 8;
  World w(settings, test::test_table(), test::weight_policy(params::PushMode::ratio, 100.0));
  const char* kinds[] = {"infantry", "light", "heavy"};
  for (int i = 0; i < 30; ++i) {
    for (int j = 0; j < 30; ++j) test::add_sphere(w, -9.0 + 0.66 * i, -9.0 + 0.66 * j, 0.35, kinds[(i + 2 * j) % 3]);
  }
  for (int t = 0; t < 100; ++t) {
    test::steer_to_origin(w);
    w.step();
  }
  Impl& m = WorldProbe::mut(w);
  bool compared = false;
  for (int t = 0; t < 60 && !compared; ++t) {
    test::steer_to_origin(w);
    // Only while a list is kept, so that the next tick refreshes the stale shares if it keeps it.
    const bool kept_before = m.list.valid;
    if (kept_before) {
      for (std::size_t k = 0; k < w.body_count(); k += 7) w.set_param(w.id_at(k), params::Param::weight_kg, 40.0 + 5.0 * (t % 40));
    }
    const StepStats& st = w.step();
    if (!kept_before || st.pair_list_reused == 0 || !m.pairs_in_list) continue;
    compared = true;
    // Pushes of 3 r (above the general cap, below the fast pairs' one) and 12 r (above both) on
    // alternate taken entries.
    for (std::size_t k = 0; k < m.list.live; ++k) m.list.lambda[m.list.of_pair[k]] = (k % 2 == 0 ? 3.0f : 12.0f) * 0.35f;
    m.schedule_list_pairs(settings.conflict_share_limit);
    const detail::PairSchedule from_list = m.pair_schedule;
    m.materialize_list_pairs();
    detail::PairSchedule from_pairs;
    detail::build_pair_schedule(m.sb, m.pairs, settings.conflict_share_limit, from_pairs);
    ASSERT_GT(from_list.fast_size(), 1000u);
    EXPECT_EQ(from_list.src, from_pairs.src);
    EXPECT_EQ(from_list.a, from_pairs.a);
    EXPECT_EQ(from_list.b, from_pairs.b);
    auto same_bits = [](const std::vector<float>& x, const std::vector<float>& y) {
      return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(float)) == 0;
    };
    EXPECT_TRUE(same_bits(from_list.nx, from_pairs.nx));
    EXPECT_TRUE(same_bits(from_list.ny, from_pairs.ny));
    EXPECT_TRUE(same_bits(from_list.pen0, from_pairs.pen0));
    EXPECT_TRUE(same_bits(from_list.target, from_pairs.target));
    EXPECT_TRUE(same_bits(from_list.share_now, from_pairs.share_now));
    EXPECT_TRUE(same_bits(from_list.share_exact, from_pairs.share_exact));
    EXPECT_TRUE(same_bits(from_list.inv_r_min, from_pairs.inv_r_min));
    EXPECT_TRUE(same_bits(from_list.lambda, from_pairs.lambda));
    // Both caps were in play.
    int carried = 0, cut = 0;
    for (const float v : from_list.lambda) {
      carried += v == 3.0f * 0.35f;
      cut += v == static_cast<float>(detail::kFastWarmStartCapOverRadius * 0.35);
    }
    EXPECT_GT(carried, 100);
    EXPECT_GT(cut, 100);
  }
  EXPECT_TRUE(compared) << "no kept tick followed a change of weights";
}

TEST(PairList, AnythingButMotionDropsTheList) {
  scene::BuiltScene b = crowd("crush", 2000, 0.2);
  World& w = b.world;
  const Impl& impl = WorldProbe::impl(w);
  // The driver steers by body id (it would not know a destroyed body): steer for a while, then let
  // the bodies keep their desired velocities.
  for (int t = 0; t < 10; ++t) step(b);
  // Runs until the list has been kept for a tick and motion alone would keep it for the next one
  // too (a twin restored from a checkpoint takes that tick unchanged: a jam's solve can move a body
  // past the margin, and the tick's second search drops the list), then applies `change` and
  // steps once.
  auto kept_after = [&](auto&& change) {
    bool motion_keeps = false;
    for (int t = 0; t < 40 && !motion_keeps; ++t) {
      // (A step that began a search in two parts, or finished one begun in three, has ended its
      // list: the next one takes the list searched.)
      const StepStats& st = w.step();
      const bool ended = (st.pair_list_searched_ahead != 0 && !impl.list.ahead_begun) || st.pair_list_ahead_finished != 0;
      if (st.pair_list_reused == 0 || ended) continue;
      std::vector<std::uint8_t> saved;
      w.save_state(saved);
      scene::BuiltScene twin = crowd("crush", 2000, 0.2);
      twin.world.restore_state(saved);
      motion_keeps = twin.world.step().pair_list_reused != 0;
    }
    EXPECT_TRUE(motion_keeps) << "no tick found whose list motion alone keeps";
    EXPECT_TRUE(impl.list.valid);
    change();
    return w.step().pair_list_reused != 0;
  };
  const ObjectId someone = w.id_at(7);
  EXPECT_FALSE(kept_after([&] { w.set_position(someone, w.position(someone)); }));
  EXPECT_TRUE(kept_after([&] { w.set_grounded(someone, true); }));  // as it was
  EXPECT_FALSE(kept_after([&] { w.set_grounded(someone, false); }));
  EXPECT_FALSE(kept_after([&] { w.set_param(someone, params::Param::collision_group, 2.0); }));
  EXPECT_FALSE(kept_after([&] { w.destroy_body(w.id_at(w.id_at(11) == someone ? 12 : 11)); }));
  EXPECT_FALSE(kept_after([&] {
    BodyDef d;
    d.position = {500.0, 500.0, 0.35};
    d.archetype = "infantry";  // the crush scene's
    w.create_body(d);
  }));
  // A parameter that only changes a resistance keeps the list, with the new shares.
  auto resistance_of = [&](ObjectId id) {
    for (std::size_t d = 0; d < impl.bodies.size(); ++d) {
      if (impl.bodies.id[d] == id) return impl.bodies.resistance[d];
    }
    return -1.0;
  };
  const double resistance_before = resistance_of(someone);
  EXPECT_TRUE(kept_after([&] { w.set_param(someone, params::Param::weight_kg, 400.0); }));
  EXPECT_NE(resistance_of(someone), resistance_before);
  std::size_t checked = 0;
  for (const TickPair& p : tick_pairs(impl)) {
    const double ra = impl.bodies.resistance[impl.solver_order[p.a]];
    const double rb = impl.bodies.resistance[impl.solver_order[p.b]];
    ASSERT_EQ(p.share_a, params::share_a_fast(ra, rb));
    checked += impl.bodies.id[impl.solver_order[p.a]] == someone || impl.bodies.id[impl.solver_order[p.b]] == someone;
  }
  EXPECT_GT(checked, 0u);
}

TEST(PairList, RestoredWorldKeepsTheListBitIdentically) {
  scene::BuiltScene a = crowd("crush", 2000, 0.2);
  // Saved just before a tick that keeps its list, after two that did: the restored world's first
  // tick must keep the saved list too (whether a given tick keeps one depends on the motion).
  std::vector<std::uint8_t> saved;
  int run = 0;
  bool found = false;
  for (int t = 0; t < 200 && !found; ++t) {
    a.world.save_state(saved);
    const bool kept = step(a).pair_list_reused != 0;
    found = kept && run >= 2;
    run = kept ? run + 1 : 0;
  }
  ASSERT_TRUE(found) << "no list kept for three ticks in a row";
  scene::BuiltScene b = crowd("crush", 2000, 0.2);
  b.world.restore_state(saved);
  EXPECT_EQ(step(b).pair_list_reused, 1u) << "the restored world searched afresh instead of keeping the saved list";
  ASSERT_EQ(a.world.state_hash(), b.world.state_hash());
  int kept = 0;
  for (int t = 0; t < 60; ++t) {
    const std::uint32_t ka = step(a).pair_list_reused;
    const std::uint32_t kb = step(b).pair_list_reused;
    ASSERT_EQ(ka, kb) << "tick " << a.world.tick();
    ASSERT_EQ(a.world.state_hash(), b.world.state_hash()) << "tick " << a.world.tick();
    kept += static_cast<int>(ka);
  }
  EXPECT_GT(kept, 20);
}

// A list searched ahead. Begun in three parts, the kept list still serves the next step: only
// ahead_begun says so (in a checkpoint and the hash too), and the step after finishes the scan and
// records the list as a restored world's list, so a checkpoint taken then holds it as any other;
// the step after that sets it up. Begun in two, the step records it at once. A world restored at
// either boundary of a three-part search searches what it needs itself (the kept list again, then
// the next one whole) and continues with the same bits; most of a marching crowd's lists are
// searched ahead in three parts, not in a tick of their own.
TEST(PairList, ListSearchedAheadRestoresBitIdentically) {
  scene::BuiltScene a = crowd("crush", 3000, 0.2);
  const Impl& impl = WorldProbe::impl(a.world);
  int begun3 = 0, begun2 = 0, whole = 0;
  bool compared_begun = false, compared_finished = false;
  auto count = [&](const StepStats& st) {
    const bool three = st.pair_list_searched_ahead != 0 && impl.list.ahead_begun;
    begun3 += three ? 1 : 0;
    begun2 += st.pair_list_searched_ahead != 0 && !three ? 1 : 0;
    whole += st.pair_list_reused == 0 && impl.list.valid ? 1 : 0;
    return three;
  };
  for (int t = 0; t < 200; ++t) {
    const StepStats& st = step(a);
    const bool three = count(st);
    if (three) {
      EXPECT_TRUE(impl.list.valid) << "the kept list serves one more step";
      EXPECT_FALSE(impl.list.restore_pending);
      EXPECT_GE(impl.list.kept_ticks, 2u);
    } else if (st.pair_list_searched_ahead != 0 || st.pair_list_ahead_finished != 0) {
      EXPECT_FALSE(impl.list.valid);
      EXPECT_TRUE(impl.list.restore_pending && impl.list.searched_ahead);
      EXPECT_FALSE(impl.list.ahead_begun);
      EXPECT_EQ(impl.list.kept_ticks, 0u);
    }
    const bool finished = st.pair_list_ahead_finished != 0;
    if (t < 20 || !((three && !compared_begun) || (finished && !compared_finished))) continue;
    (three ? compared_begun : compared_finished) = true;
    SCOPED_TRACE(three ? "restored after a search was begun" : "restored after its scan was finished");
    std::vector<std::uint8_t> saved;
    a.world.save_state(saved);
    scene::BuiltScene b = crowd("crush", 3000, 0.2);
    b.world.restore_state(saved);
    ASSERT_EQ(a.world.state_hash(), b.world.state_hash());
    const Impl& restored = WorldProbe::impl(b.world);
    EXPECT_FALSE(restored.list.searched_ahead) << "a restored world has no scan under way";
    EXPECT_FALSE(restored.list.ahead_built);
    EXPECT_EQ(restored.list.ahead_begun, three);
    // Both worlds step on with the same driver inputs (the drivers are the same scene's).
    b.driver = a.driver;
    for (int k = 0; k < 60; ++k) {
      const StepStats sa = step(a);
      const StepStats sb = step(b);
      if (k == 0) {
        EXPECT_EQ(sa.pair_list_reused, 1u) << (three ? "the kept list did not serve" : "the list searched ahead was not taken");
        EXPECT_EQ(sb.pair_list_reused, 1u);
        if (three) {
          EXPECT_EQ(sa.pair_list_ahead_finished, 1u);
          EXPECT_EQ(sb.pair_list_ahead_finished, 1u);
        }
      }
      ASSERT_EQ(sa.pair_list_reused, sb.pair_list_reused) << "tick " << sa.tick;
      ASSERT_EQ(sa.pair_list_searched_ahead, sb.pair_list_searched_ahead) << "tick " << sa.tick;
      ASSERT_EQ(sa.pair_list_ahead_finished, sb.pair_list_ahead_finished) << "tick " << sa.tick;
      ASSERT_EQ(a.world.state_hash(), b.world.state_hash()) << "tick " << sa.tick;
      count(sa);
    }
    t += 60;
  }
  EXPECT_TRUE(compared_begun) << "no step began a search in three parts";
  EXPECT_TRUE(compared_finished) << "no step finished one";
  EXPECT_GT(begun3, 2 * begun2) << begun3 << " begun in three parts, " << begun2 << " in two";
  EXPECT_GT(begun3 + begun2, 3 * whole) << begun3 + begun2 << " lists searched ahead, " << whole << " in a tick of their own";
}

// Whatever tick boundary a checkpoint is taken at (inside a list, between the parts of a search
// ahead, right after a whole search), a twin restored from it on another number of threads steps
// on bit-identically. Over 100 boundaries of a marching crowd.
TEST(PairList, ARestoreAtEveryTickBoundaryContinuesBitIdentically) {
  scene::BuiltScene a = crowd("crush", 3000, 0.2);
  const Impl& impl = WorldProbe::impl(a.world);
  for (int t = 0; t < 20; ++t) step(a);
  constexpr int kBoundaries = 100, kFollow = 3;
  std::vector<std::vector<std::uint8_t>> saves(kBoundaries);
  std::vector<scene::SceneDriver> drivers;
  std::vector<std::uint64_t> hashes;
  int begun3 = 0, finished = 0;
  for (int t = 0; t < kBoundaries + kFollow; ++t) {
    if (t < kBoundaries) {
      a.world.save_state(saves[static_cast<std::size_t>(t)]);
      drivers.push_back(a.driver);
    }
    const StepStats& st = step(a);
    hashes.push_back(a.world.state_hash());
    begun3 += st.pair_list_searched_ahead != 0 && impl.list.ahead_begun ? 1 : 0;
    finished += static_cast<int>(st.pair_list_ahead_finished);
  }
  EXPECT_GE(begun3, 5);
  EXPECT_GE(finished, 5);
  for (int t = 0; t < kBoundaries; ++t) {
    scene::BuiltScene b = crowd("crush", 3000, 0.2, 2);
    b.world.restore_state(saves[static_cast<std::size_t>(t)]);
    b.driver = drivers[static_cast<std::size_t>(t)];
    for (int k = 0; k < kFollow; ++k) {
      step(b);
      ASSERT_EQ(b.world.state_hash(), hashes[static_cast<std::size_t>(t + k)])
          << "restored at boundary " << t << ", step " << k + 1 << " after it";
    }
  }
}

// Anything that drops a list between the parts of a search ahead drops the search begun too: the
// next step searches afresh where the bodies are, as a restored twin does. A change of weight keeps
// both, and the finished list takes the new shares, as the twin's whole search does.
TEST(PairList, ChangeAfterSearchAheadDropsItOrKeepsItAsARestoredTwin) {
  struct Change {
    const char* what;
    bool keeps;
    void (*apply)(World&);
  };
  const Change changes[] = {
      {"teleport by 1 mm", false,
       [](World& w) {
         const ObjectId id = w.id_at(5);
         const Vec3 p = w.position(id);
         w.set_position(id, Vec3{p.x + 0.001, p.y, p.z});
       }},
      {"lifted", false, [](World& w) { w.set_grounded(w.id_at(5), false); }},
      {"grounded as it was", true, [](World& w) { w.set_grounded(w.id_at(5), true); }},
      {"collision group", false, [](World& w) { w.set_param(w.id_at(5), params::Param::collision_group, 2.0); }},
      {"weight", true, [](World& w) { w.set_param(w.id_at(5), params::Param::weight_kg, 400.0); }},
      {"destroyed", false, [](World& w) { w.destroy_body(w.id_at(11)); }},
      {"created", false,
       [](World& w) {
         BodyDef d;
         d.position = {500.0, 500.0, 0.35};
         d.archetype = "infantry";  // the crush scene's
         w.create_body(d);
       }},
  };
  for (const Change& change : changes) {
    // After the step that began a search in three parts (the kept list serves one more step), and
    // after the step that finished its scan (the list searched is the next step's).
    for (const bool finished : {false, true}) {
      SCOPED_TRACE(change.what);
      SCOPED_TRACE(finished ? "after the scan was finished" : "after the search was begun");
      scene::BuiltScene a = crowd("crush", 3000, 0.2);
      bool found = false;
      for (int t = 0; t < 200 && !found; ++t) {
        const StepStats& st = step(a);
        const bool begun = st.pair_list_searched_ahead != 0 && WorldProbe::impl(a.world).list.ahead_begun;
        found = t > 20 && (finished ? st.pair_list_ahead_finished != 0 : begun);
      }
      ASSERT_TRUE(found);
      std::vector<std::uint8_t> saved;
      a.world.save_state(saved);
      scene::BuiltScene b = crowd("crush", 3000, 0.2);
      b.world.restore_state(saved);
      change.apply(a.world);
      change.apply(b.world);
      ASSERT_EQ(a.world.state_hash(), b.world.state_hash());
      // (The bodies keep their desired velocities from here: the driver steers by id.)
      for (int t = 0; t < 30; ++t) {
        const StepStats sa = a.world.step();
        const StepStats sb = b.world.step();
        if (t == 0) {
          EXPECT_EQ(sa.pair_list_reused, change.keeps ? 1u : 0u);
          // Kept after a begin, the step finishes the scan (the twin builds the grid to do so).
          if (change.keeps && !finished) {
            EXPECT_EQ(sa.pair_list_ahead_finished, 1u);
          }
        }
        ASSERT_EQ(sa.pair_list_reused, sb.pair_list_reused) << "tick " << sa.tick;
        ASSERT_EQ(sa.pair_list_searched_ahead, sb.pair_list_searched_ahead) << "tick " << sa.tick;
        ASSERT_EQ(sa.pair_list_ahead_finished, sb.pair_list_ahead_finished) << "tick " << sa.tick;
        ASSERT_EQ(a.world.state_hash(), b.world.state_hash()) << "tick " << sa.tick;
      }
    }
  }
}

// A change between the restore and the next step drops the restored list as it drops the saved
// world's: both search afresh, and the state hash says so before the step already.
TEST(PairList, ChangeAfterRestoreDropsTheRestoredListToo) {
  scene::BuiltScene a = crowd("crush", 2000, 0.2);
  int run = 0;
  for (int t = 0; t < 100 && run < 2; ++t) run = step(a).pair_list_reused != 0 ? run + 1 : 0;
  ASSERT_EQ(run, 2);
  std::vector<std::uint8_t> saved;
  a.world.save_state(saved);
  scene::BuiltScene b = crowd("crush", 2000, 0.2);
  b.world.restore_state(saved);
  ASSERT_EQ(a.world.state_hash(), b.world.state_hash());
  // A 1 mm teleport: well within the skin, so only the drop tells the worlds to search afresh.
  const ObjectId id = a.world.id_at(5);
  for (World* w : {&a.world, &b.world}) {
    const Vec3 p = w->position(id);
    w->set_position(id, Vec3{p.x + 0.001, p.y, p.z});
  }
  ASSERT_EQ(a.world.state_hash(), b.world.state_hash());
  for (int t = 0; t < 30; ++t) {
    const std::uint32_t ka = step(a).pair_list_reused;
    const std::uint32_t kb = step(b).pair_list_reused;
    ASSERT_EQ(ka, kb) << "tick " << a.world.tick();
    ASSERT_EQ(a.world.state_hash(), b.world.state_hash()) << "tick " << a.world.tick();
    if (t == 0) {
      EXPECT_EQ(ka, 0u);
    }
  }
}

TEST(PairList, CheckpointRejectsABrokenList) {
  scene::BuiltScene a = crowd("crush", 500, 0.2);
  for (int t = 0; t < 200 && !WorldProbe::impl(a.world).list.valid; ++t) step(a);
  ASSERT_TRUE(WorldProbe::impl(a.world).list.valid);
  std::vector<std::uint8_t> saved;
  a.world.save_state(saved);
  // The list's positions are the last bytes of the section: the last body's z.
  std::vector<std::uint8_t> bad = saved;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(bad.data() + bad.size() - 8, &nan, 8);
  scene::BuiltScene b = crowd("crush", 500, 0.2);
  const std::uint64_t before = b.world.state_hash();
  try {
    b.world.restore_state(bad);
    ADD_FAILURE() << "a NaN list position was accepted";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("pair list"), std::string::npos) << e.what();
  }
  saved.pop_back();
  EXPECT_THROW(b.world.restore_state(saved), CheckpointError);
  EXPECT_EQ(b.world.state_hash(), before);
}

// Two columns passing each other at 9 m/s (0.15 m a tick each): every list is outrun in its first
// tick, so the world searches without a list for kCooldownTicks ticks, then twice as long after
// each further list that did not pay.
// A crowd that packs tighter has more pairs per list than at its first search. The list's columns
// keep room for that: a later, longer list must not reallocate them (a tick that did was the
// slowest of a 20,000-body run after the first few, its memory faulted in anew).
TEST(PairList, ColumnsKeepRoomForListsLongerThanTheFirst) {
  scene::BuiltScene b = scene::build_scene(scene::scale_scene(scene::builtin_scene("crush"), 3000));
  const Impl& w = WorldProbe::impl(b.world);
  // Each column's data and capacity, in one list.
  const auto columns = [&] {
    const Impl::PairList& l = w.list;
    const auto at = [](const auto& v) { return std::pair<const void*, std::size_t>{v.data(), v.capacity()}; };
    return std::vector<std::pair<const void*, std::size_t>>{at(l.a),     at(l.b),      at(l.target), at(l.reach),
                                                            at(l.share), at(l.lambda), at(l.slot),   at(l.of_pair)};
  };
  // The first search's entries (its tick may still drop the list: a second search after deep spawn
  // overlaps).
  for (int t = 0; t < 10 && w.list.a.empty(); ++t) step(b);
  const std::size_t first = w.list.a.size();
  ASSERT_GT(first, 0u) << "no list searched in 10 ticks";
  const auto where = columns();
  for (const auto& [data, capacity] : where) EXPECT_GE(capacity, 2 * first);
  const Impl::PairList& l = w.list;
  std::size_t longest = first;
  for (int t = 0; t < 300 && longest <= 2 * first; ++t) {
    step(b);
    longest = std::max(longest, l.a.size());
    if (l.a.size() <= 2 * first) {
      ASSERT_EQ(columns(), where) << "a list of " << l.a.size() << " entries (the first had " << first
                                  << ") moved the columns, tick " << b.world.tick();
    }
  }
  EXPECT_GT(longest, first) << "no list outgrew the first: the test shows nothing";
}

TEST(PairList, TooFastForTheSkinSearchesWithoutAListForLongerAndLonger) {
  WorldSettings s;
  World w(s, test::test_table(), test::weight_policy(params::PushMode::ratio, 100.0));
  for (int k = 0; k < 200; ++k) {
    // 0.8 m apart within a column (pairs of the list, not of the margin), columns 2 m apart.
    const ObjectId id = test::add_sphere(w, k % 2 == 0 ? -1.0 : 1.0, 0.8 * (k / 2));
    w.set_desired_velocity(id, Vec3{0.0, k % 2 == 0 ? 9.0 : -9.0, 0.0});
  }
  const Impl& impl = WorldProbe::impl(w);
  std::vector<std::uint64_t> searches;
  for (int t = 0; t < 60; ++t) {
    const bool cooling = impl.list.cooldown > 0;
    const StepStats& st = w.step();
    EXPECT_EQ(st.pair_list_reused, 0u) << "tick " << st.tick;
    if (impl.list.valid) {
      searches.push_back(st.tick);
      EXPECT_FALSE(cooling);
    }
  }
  // Searched at tick 1, outrun at 2 (cooldown 8: ticks 2-9), searched at 10, outrun at 11
  // (cooldown 16: 11-26), searched at 27, outrun at 28 (cooldown 32: 28-59), searched at 60.
  const std::uint32_t c = Impl::PairList::kCooldownTicks;
  EXPECT_EQ(searches, (std::vector<std::uint64_t>{1, 2 + c, 3 + 3 * c, 4 + 7 * c}));
  EXPECT_EQ(impl.list.backoff, 8 * c);
}

}  // namespace
}  // namespace throng
