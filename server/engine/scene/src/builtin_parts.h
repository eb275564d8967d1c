#pragma once
// Short constructors for the built-in scenes, so each scene reads as a layout, not as field
// assignments.
#include <string>
#include <utility>

#include "throng/scene/scene_def.h"

namespace throng::scene::detail {

// Heights of the standard bodies: centre z = radius + half_height puts the feet on z = 0.
inline constexpr double kFootRadius_m = 0.35;
inline constexpr double kFootHalfHeight_m = 0.55;  // 1.8 m tall
inline constexpr double kMountRadius_m = 0.7;
inline constexpr double kMountHalfHeight_m = 0.6;
inline constexpr double kGiantRadius_m = 1.4;
inline constexpr double kGiantHalfHeight_m = 1.6;  // 6 m tall

inline Scenery box(Vec3 centre, Vec3 half_extents_m, double yaw_deg, std::string archetype = "wall") {
  Scenery s;
  s.kind = SceneryKind::box;
  s.archetype = std::move(archetype);
  s.centre = centre;
  s.half_extents_m = half_extents_m;
  s.yaw_deg = yaw_deg;
  return s;
}

inline Scenery cylinder(Vec3 centre, double radius_m, double half_height_m, std::string archetype = "wall") {
  Scenery s;
  s.kind = SceneryKind::cylinder;
  s.archetype = std::move(archetype);
  s.centre = centre;
  s.radius_m = radius_m;
  s.half_height_m = half_height_m;
  return s;
}

inline SpawnShape disk(Vec2 centre, double radius_m) {
  SpawnShape s;
  s.kind = SpawnAreaKind::disk;
  s.centre = centre;
  s.radius_m = radius_m;
  return s;
}

inline SpawnShape rect(Vec2 centre, Vec2 half_extents_m, double yaw_deg = 0.0) {
  SpawnShape s;
  s.kind = SpawnAreaKind::rect;
  s.centre = centre;
  s.half_extents_m = half_extents_m;
  s.yaw_deg = yaw_deg;
  return s;
}

inline SpawnShape point(Vec2 centre) {
  SpawnShape s;
  s.kind = SpawnAreaKind::point;
  s.centre = centre;
  return s;
}

inline Behavior seek(Vec2 target, double speed_mps) {
  return {BehaviorKind::seek_point, target, true, {}, speed_mps};
}

inline Behavior march(Vec2 direction, double speed_mps) {
  return {BehaviorKind::march, {}, false, direction, speed_mps};
}

inline SpawnGroup group(std::string name, std::uint32_t count, SpawnShape shape, double radius_m, double half_height_m,
                        std::string archetype, Behavior behavior) {
  SpawnGroup g;
  g.name = std::move(name);
  g.count = count;
  g.shape = shape;
  g.radius_m = radius_m;
  g.half_height_m = half_height_m;
  g.archetype = std::move(archetype);
  g.behavior = behavior;
  return g;
}

inline SpawnGroup foot(std::string name, std::uint32_t count, SpawnShape shape, std::string archetype, Behavior b) {
  return group(std::move(name), count, shape, kFootRadius_m, kFootHalfHeight_m, std::move(archetype), b);
}

}  // namespace throng::scene::detail
