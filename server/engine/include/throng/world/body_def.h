#pragma once
// What a movable character is made of when it is created. Characters are kinematic upright
// capsules (half_height 0 = sphere): foot soldiers, horses, giants differ only in the numbers.
#include <cstdint>
#include <string>

#include "throng/core/vec3.h"

namespace throng {

struct BodyDef {
  Vec3 position;               // centre of the capsule [m], finite
  double radius_m = 0.35;      // (0, 100]
  double half_height_m = 0.0;  // half length of the vertical core segment [0, 100]
  // Grounded bodies stand on something: they are pushed only in the ground plane (the contact is
  // still computed in 3D, so a rider over a foot soldier needs less horizontal separation).
  // Airborne bodies (jumping, falling) take the full 3D push.
  bool grounded = true;
  std::string archetype = "infantry";  // name in the parameter table
  std::uint32_t collision_id = 0;      // the patent's collision id (per-collision overrides)
};

}  // namespace throng
