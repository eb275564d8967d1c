// Built-in crowd scenes without walls: crush, one_cell, mixed (catalogue in builtin_scenes.h).
#include <cmath>

#include "builtin_catalogue.h"
#include "builtin_parts.h"

namespace throng::scene::detail {

SceneDef crush_scene() {
  constexpr std::uint32_t kAgents = 20'000;
  SceneDef s;
  s.name = "crush";
  s.description = "20,000 spheres (r 0.35 m) uniform in a disk of radius 0.5*sqrt(N), all seeking the centre at 1.5 m/s";
  s.ticks = 300;
  // Disk area pi * 0.25 * N: 1.27 bodies per m^2, about half the ground covered at the start,
  // and everyone then walks into the middle — the worst sustained density a battle produces.
  SpawnGroup g = group("crowd", kAgents, disk({0.0, 0.0}, 0.5 * std::sqrt(double(kAgents))), kFootRadius_m, 0.0,
                       "infantry", seek({0.0, 0.0}, 1.5));
  s.spawns.push_back(g);
  return s;
}

SceneDef one_cell_scene() {
  constexpr std::uint32_t kAgents = 20'000;
  SceneDef s;
  s.name = "one_cell";
  s.description = "every body starts at one point (broadphase worst case); bodies idle and are only pushed apart";
  s.ticks = 300;
  s.spawns.push_back(group("heap", kAgents, point({0.0, 0.0}), kFootRadius_m, 0.0, "infantry", Behavior{}));
  return s;
}

SceneDef mixed_scene() {
  SceneDef s;
  s.name = "mixed";
  s.description = "light and heavy foot, cavalry and giants mixed in one disk, all converging on the centre";
  s.ticks = 300;
  // Footprints: 8,000 x 0.385 + 1,500 x 1.54 + 500 x 6.16 m^2 ~ 8,500 m^2, half of the disk.
  const SpawnShape area = disk({0.0, 0.0}, 75.0);
  const Vec2 centre{0.0, 0.0};
  s.spawns.push_back(foot("light foot", 5'000, area, "light", seek(centre, 1.6)));
  s.spawns.push_back(foot("heavy foot", 3'000, area, "heavy", seek(centre, 1.2)));
  s.spawns.push_back(group("cavalry", 1'500, area, kMountRadius_m, kMountHalfHeight_m, "cavalry", seek(centre, 2.5)));
  s.spawns.push_back(group("giants", 500, area, kGiantRadius_m, kGiantHalfHeight_m, "giant", seek(centre, 1.0)));
  return s;
}

}  // namespace throng::scene::detail
