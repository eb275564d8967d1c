// The NPC AI inside a match (battle scene) and on its own (small worlds).
#include <nlohmann/json.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include "../../server/match/src/npc_ai.h"
#include "match_test_util.h"
#include "throng/match/match.h"
#include "throng/params/object_params.h"
#include "throng/scene/build_scene.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"
#include "throng/world/world.h"

namespace throng::match {
namespace {

struct Centroids {
  double x[3] = {0, 0, 0};
  double y[3] = {0, 0, 0};
};

Centroids faction_centroids(const World& w) {
  Centroids c;
  int n[3] = {0, 0, 0};
  for (std::size_t d = 0; d < w.body_count(); ++d) {
    const auto f = w.params(w.id_at(d)).faction;
    if (f > 2) continue;
    c.x[f] += w.pos_x()[d];
    c.y[f] += w.pos_y()[d];
    ++n[f];
  }
  for (int f = 0; f < 3; ++f) {
    if (n[f] > 0) {
      c.x[f] /= n[f];
      c.y[f] /= n[f];
    }
  }
  return c;
}

double faction_gap(const World& w) {
  const Centroids c = faction_centroids(w);
  return std::hypot(c.x[1] - c.x[2], c.y[1] - c.y[2]);
}

std::uint32_t enemy_contacts(const World& w) {
  std::uint32_t n = 0;
  for (const PushEvent& e : w.push_events()) {
    if (!w.is_body(e.a) || !w.is_body(e.b)) continue;
    const auto fa = w.params(e.a).faction;
    const auto fb = w.params(e.b).faction;
    if (fa != fb && fa != 0 && fb != 0) ++n;
  }
  return n;
}

TEST(NpcAi, BattleArmiesCloseInAndPressIntoEachOther) {
  Match m(scene::scale_scene(scene::builtin_scene("battle"), 400), test::small_config(), "battle");
  Outbox out;
  const double gap0 = faction_gap(m.world());
  ASSERT_GT(gap0, 15.0);
  double gap_prev = gap0;
  std::uint32_t contacts = 0;
  int first_contact_tick = -1;
  for (int t = 1; t <= 600; ++t) {
    m.tick(out);
    const std::uint32_t c = enemy_contacts(m.world());
    if (c > 0 && first_contact_tick < 0) first_contact_tick = t;
    contacts += c;
    if (t % 150 == 0) {
      const double gap = faction_gap(m.world());
      // Closing in (until they meet; then the front holds and the gap stays small).
      if (gap_prev > 8.0) {
        EXPECT_LT(gap, gap_prev - 2.0) << "tick " << t;
      }
      gap_prev = gap;
    }
  }
  EXPECT_LT(faction_gap(m.world()), 0.5 * gap0);
  EXPECT_GT(first_contact_tick, 0);
  EXPECT_GT(contacts, 1000u);  // many enemy pairs pushed, over many ticks
  // Still pressing at the end.
  EXPECT_GT(enemy_contacts(m.world()), 10u);
}

// Two formations, group 2's base morale broken in the scene's parameter table.
scene::SceneDef armies_with_morale(double group2_morale) {
  scene::SceneDef s = test::two_armies(60, 24.0, 4.0);
  nlohmann::json doc = nlohmann::json::parse(R"({
    "archetypes": {
      "infantry": { "kind": "foot", "weight": 80 },
      "wall": { "kind": "scenery", "character_type": "prop", "fixed": true },
      "bush": { "kind": "scenery", "character_type": "prop", "fixed": true, "softness": 0.6 }
    },
    "groups": [ { "id": 1 }, { "id": 2 } ]
  })");
  doc["groups"][1]["morale"] = group2_morale;
  s.params.inline_json = doc.dump();
  return s;
}

double group_x(const World& w, std::uint32_t group) {
  double sx = 0;
  int n = 0;
  for (std::size_t d = 0; d < w.body_count(); ++d) {
    if (w.params(w.id_at(d)).group_id != group) continue;
    sx += w.pos_x()[d];
    ++n;
  }
  return sx / n;
}

TEST(NpcAi, LowMoraleGroupRetreats) {
  Match broken(armies_with_morale(-50.0), test::small_config(), "broken");
  Match steady(armies_with_morale(0.0), test::small_config(), "steady");
  Outbox out;
  const double start2 = group_x(broken.world(), 2);  // group 2 starts on the right (+x)
  const double start1 = group_x(broken.world(), 1);
  ASSERT_EQ(start2, group_x(steady.world(), 2));
  for (int t = 0; t < 150; ++t) {
    broken.tick(out);
    steady.tick(out);
  }
  // 5 s at 1.2 m/s: the broken group fell back east, the steady one advanced west.
  EXPECT_GT(group_x(broken.world(), 2), start2 + 3.0);
  EXPECT_LT(group_x(steady.world(), 2), start2 - 3.0);
  // Group 1 advances in both.
  EXPECT_GT(group_x(broken.world(), 1), start1 + 3.0);
  // The broken group keeps its distance: no enemy contact.
  EXPECT_EQ(enemy_contacts(broken.world()), 0u);
  // Its side is routed (its only group retreats); nobody is in the steady match.
  EXPECT_EQ(broken.routed_faction(), std::optional<std::uint8_t>(2));
  EXPECT_EQ(steady.routed_faction(), std::nullopt);
}

// A side is routed when every one of its groups that still has NPCs retreats; the neutral
// faction, empty groups and a side with one group holding never are.
TEST(NpcAi, RoutedFactionNeedsEveryFieldedGroupRetreating) {
  auto group = [](std::uint8_t faction, std::uint32_t npcs, bool retreating) {
    AiGroup g;
    g.faction = faction;
    g.npcs = npcs;
    g.members = npcs;
    g.retreating = retreating;
    return g;
  };
  EXPECT_EQ(routed_faction(std::vector<AiGroup>{}), std::nullopt);
  EXPECT_EQ(routed_faction(std::vector<AiGroup>{group(1, 10, false), group(2, 10, false)}), std::nullopt);
  EXPECT_EQ(routed_faction(std::vector<AiGroup>{group(1, 10, false), group(2, 10, true), group(2, 5, true)}),
            std::optional<std::uint8_t>(2));
  EXPECT_EQ(routed_faction(std::vector<AiGroup>{group(2, 10, true), group(2, 5, false)}), std::nullopt)
      << "one group of the side still holds";
  EXPECT_EQ(routed_faction(std::vector<AiGroup>{group(2, 10, true), group(2, 0, false)}), std::optional<std::uint8_t>(2))
      << "a group without NPCs (players only) does not hold the side";
  EXPECT_EQ(routed_faction(std::vector<AiGroup>{group(0, 10, true)}), std::nullopt) << "neutral is never routed";
  EXPECT_EQ(routed_faction(std::vector<AiGroup>{group(3, 1, true), group(2, 1, true)}), std::optional<std::uint8_t>(2))
      << "the lowest faction first";
}

// Runs the AI on its own over a built scene, following the World's dense re-sorts like Match does.
struct AiRun {
  explicit AiRun(const scene::SceneDef& s) : built(scene::build_scene(s)), ai(settings_for(built.world)) {
    ai.init(built.world);
    controlled.assign(built.world.body_count(), 0);
    yaw.assign(built.world.body_count(), 42.0f);
  }
  static NpcAiSettings settings_for(const World& w) {
    NpcAiSettings s;
    s.dt_s = w.settings().dt_s;
    return s;
  }
  std::uint32_t tick() {
    const std::uint32_t engaged = ai.update(built.world, controlled, yaw);
    built.world.step();
    const std::span<const std::uint32_t> perm = built.world.last_reorder();
    if (!perm.empty()) {
      ai.apply_reorder(perm);
      std::vector<std::uint32_t> c(perm.size());
      std::vector<float> y(perm.size());
      for (std::size_t d = 0; d < perm.size(); ++d) {
        c[d] = controlled[perm[d]];
        y[d] = yaw[perm[d]];
      }
      controlled.swap(c);
      yaw.swap(y);
      ++reorders;
    }
    return engaged;
  }
  std::size_t dense_of(ObjectId id) const { return built.world.dense_index(id).value_or(0); }
  scene::BuiltScene built;
  NpcAi ai;
  std::vector<std::uint32_t> controlled;
  std::vector<float> yaw;
  int reorders = 0;
};

TEST(NpcAi, YawFollowsMotionAndControlledBodiesAreSkipped) {
  AiRun run(test::two_armies(10, 40.0, 2.0));
  const World& w = run.built.world;
  const ObjectId player = w.id_at(0);
  run.controlled[0] = 1;
  const double anchor0 = run.ai.groups()[0].anchor_x;
  const double anchor1 = run.ai.groups()[1].anchor_x;
  for (int t = 0; t < 60; ++t) run.tick();
  EXPECT_GT(run.reorders, 0);  // the World re-sorted its bodies meanwhile
  const std::size_t p = run.dense_of(player);
  EXPECT_EQ(run.controlled[p], 1u);
  EXPECT_EQ(run.yaw[p], 42.0f);  // never touched
  EXPECT_LT(std::hypot(w.velocity(player).x, w.velocity(player).y), 0.8);  // only pushed, never driven
  for (std::size_t d = 0; d < w.body_count(); ++d) {
    if (d == p) continue;
    const auto f = w.params(w.id_at(d)).faction;
    // Marching at each other: faction 1 (west) faces +x, faction 2 faces -x.
    const double expected = f == 1 ? 0.0 : std::numbers::pi;
    const double diff = std::remainder(static_cast<double>(run.yaw[d]) - expected, 2.0 * std::numbers::pi);
    EXPECT_LT(std::abs(diff), 0.6) << "body " << d << " faction " << int(f);
  }
  ASSERT_EQ(run.ai.groups().size(), 2u);
  // Anchors advanced towards each other (60 ticks of 1/60 s at 1.2 m/s, waiting on the leash).
  EXPECT_GT(run.ai.groups()[0].anchor_x, anchor0 + 0.9);
  EXPECT_LT(run.ai.groups()[1].anchor_x, anchor1 - 0.9);
  EXPECT_EQ(run.ai.groups()[0].target_group, 1);
  EXPECT_EQ(run.ai.groups()[1].target_group, 0);
}

TEST(NpcAi, CloseEnemiesAreChargedAndLoneFormationsHold) {
  // One body each side, 8 m apart: inside the engagement radius, each heads straight for the other
  // (each NPC looks for the nearest enemy every kTargetRefreshTicks ticks, staggered).
  AiRun duel(test::two_armies(1, 8.0, 0.01));
  std::uint32_t engaged = 0;
  for (std::uint32_t t = 0; t < kTargetRefreshTicks; ++t) engaged = duel.tick();
  EXPECT_EQ(engaged, 2u);
  const World& w = duel.built.world;
  for (std::size_t d = 0; d < 2; ++d) {
    const Vec3 v = w.velocity(w.id_at(d));
    const double toward = w.pos_x()[d] < 0 ? 1.0 : -1.0;
    EXPECT_NEAR(v.x, toward * duel.ai.settings().speed_mps, 1e-6);
    EXPECT_NEAR(v.y, 0.0, 1e-3);  // the spawn rect is 2 cm tall
  }

  // A single faction has no enemy: everyone stays in formation.
  scene::SceneDef lone = test::two_armies(30, 30.0, 4.0);
  lone.spawns.pop_back();
  AiRun hold(lone);
  const World& w2 = hold.built.world;
  // Let the spawn overlaps settle first.
  for (int t = 0; t < 10; ++t) hold.tick();
  std::vector<std::pair<ObjectId, double>> x0;
  for (std::size_t d = 0; d < w2.body_count(); ++d) x0.emplace_back(w2.id_at(d), w2.pos_x()[d]);
  for (int t = 0; t < 60; ++t) EXPECT_EQ(hold.tick(), 0u);
  for (const auto& [id, x] : x0) EXPECT_NEAR(w2.position(id).x, x, 0.3);
  EXPECT_EQ(hold.ai.groups()[0].target_group, -1);
}

}  // namespace
}  // namespace throng::match
