// Built-in scenes with walls and obstacles: street, obstacles, battle (catalogue in builtin_scenes.h).
#include "builtin_catalogue.h"
#include "builtin_parts.h"

namespace throng::scene::detail {
namespace {

void set_side(SpawnGroup& g, std::uint32_t faction, std::uint32_t group_id) {
  g.faction = faction;
  g.group = group_id;
}

}  // namespace

SceneDef street_scene() {
  SceneDef s;
  s.name = "street";
  s.description = "two armies (factions 1 and 2) march at each other down a 20 m street between two long walls";
  s.ticks = 600;
  // Walls 200 m long, inner faces at y = +-10; 3 m high.
  s.scenery.push_back(box({0.0, 10.5, 1.5}, {100.0, 0.5, 1.5}, 0.0));
  s.scenery.push_back(box({0.0, -10.5, 1.5}, {100.0, 0.5, 1.5}, 0.0));
  // Each army: 1,300 infantry behind a front of 400 heavies, ~1.4 bodies per m^2; fronts 10 m apart.
  for (int side = 0; side < 2; ++side) {
    const double sign = side == 0 ? -1.0 : 1.0;  // red on the west (-x), blue on the east
    const std::uint32_t faction = side == 0 ? 1u : 2u;
    const Behavior go = march({-sign, 0.0}, 1.3);
    SpawnGroup heavy = foot(side == 0 ? "red heavy" : "blue heavy", 400, rect({sign * 12.5, 0.0}, {7.5, 9.5}), "heavy", go);
    SpawnGroup inf = foot(side == 0 ? "red infantry" : "blue infantry", 1'300, rect({sign * 45.0, 0.0}, {25.0, 9.5}),
                          "infantry", go);
    set_side(heavy, faction, 2 * faction - 1);
    set_side(inf, faction, 2 * faction);
    s.spawns.push_back(heavy);
    s.spawns.push_back(inf);
  }
  return s;
}

SceneDef obstacles_scene() {
  SceneDef s;
  s.name = "obstacles";
  s.description = "a crowd marching through pillars, crates, soft bushes and cushions into a walled pen";
  s.ticks = 600;
  // Pen: x in [-30, 30], y in [-20, 20], open at the back (west) where the crowd starts.
  s.scenery.push_back(box({30.5, 0.0, 1.5}, {0.5, 21.0, 1.5}, 0.0));
  s.scenery.push_back(box({0.0, 20.5, 1.5}, {30.0, 0.5, 1.5}, 0.0));
  s.scenery.push_back(box({0.0, -20.5, 1.5}, {30.0, 0.5, 1.5}, 0.0));
  // Columns of obstacles, each kind offset so no lane is straight.
  for (int i = -2; i <= 2; ++i) s.scenery.push_back(cylinder({4.0, 7.5 * i, 1.5}, 0.6, 1.5, "wall"));           // pillars
  for (int i = -2; i <= 1; ++i) s.scenery.push_back(box({10.0, 7.5 * i + 3.75, 0.7}, {1.0, 0.7, 0.7}, 30.0, "wall"));  // crates
  for (int i = -2; i <= 2; ++i) s.scenery.push_back(cylinder({16.0, 7.5 * i, 0.6}, 1.5, 0.6, "bush"));          // soft
  for (int i = -1; i <= 1; ++i) s.scenery.push_back(box({23.0, 10.0 * i + 5.0, 0.5}, {1.5, 1.5, 0.5}, 45.0, "cushion"));
  s.spawns.push_back(foot("crowd", 1'500, rect({-16.0, 0.0}, {14.0, 19.0}), "infantry", march({1.0, 0.0}, 1.6)));
  return s;
}

SceneDef battle_scene() {
  SceneDef s;
  s.name = "battle";
  s.description = "the default battle: two factions of 1,700 NPCs each (infantry, heavies, cavalry), ruined walls, bushes";
  s.ticks = 600;
  s.scenery.push_back(box({0.0, 22.0, 1.0}, {6.0, 0.4, 1.0}, 20.0));    // ruined walls
  s.scenery.push_back(box({3.0, -18.0, 1.0}, {5.0, 0.4, 1.0}, -35.0));
  s.scenery.push_back(box({-4.0, -40.0, 1.0}, {8.0, 0.4, 1.0}, 80.0));
  s.scenery.push_back(cylinder({0.0, 45.0, 4.0}, 3.0, 4.0, "wall"));      // a tower
  s.scenery.push_back(cylinder({0.0, 5.0, 0.6}, 1.5, 0.6, "bush"));
  s.scenery.push_back(cylinder({-9.0, -30.0, 0.6}, 2.0, 0.6, "bush"));
  s.scenery.push_back(cylinder({10.0, 32.0, 0.6}, 2.0, 0.6, "bush"));
  for (int side = 0; side < 2; ++side) {
    const double sign = side == 0 ? -1.0 : 1.0;
    const std::uint32_t faction = side == 0 ? 1u : 2u;
    const std::string team = side == 0 ? "red " : "blue ";
    // ~0.83 bodies per m^2: loose ranks that compress when the lines meet.
    SpawnGroup inf = foot(team + "infantry", 1'200, rect({sign * 45.0, 0.0}, {12.0, 30.0}), "infantry", march({-sign, 0.0}, 1.2));
    SpawnGroup heavy = foot(team + "heavy", 400, rect({sign * 28.0, 0.0}, {4.0, 30.0}), "heavy", march({-sign, 0.0}, 1.2));
    // Cavalry on the north flank, charging diagonally into the enemy's side.
    SpawnGroup cav = group(team + "cavalry", 100, rect({sign * 40.0, 40.0}, {10.0, 6.0}), kMountRadius_m,
                           kMountHalfHeight_m, "cavalry", march({-sign, -0.3}, 3.0));
    set_side(inf, faction, 3 * faction - 2);
    set_side(heavy, faction, 3 * faction - 1);
    set_side(cav, faction, 3 * faction);
    s.spawns.push_back(inf);
    s.spawns.push_back(heavy);
    s.spawns.push_back(cav);
  }
  return s;
}

}  // namespace throng::scene::detail
