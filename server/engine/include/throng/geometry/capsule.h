#pragma once
// Character collision shapes and the contact record shared by every geometry query.
//
// A capsule is the set of points within `radius` of its core segment p0..p1; characters are
// capsules because the pairwise contact is exact in closed form (segment-segment distance minus
// radii) and it is the one shape that slides round corners without snagging.
#include "throng/core/vec3.h"

namespace throng::geom {

// General capsule: core segment p0..p1 (any orientation; p0 == p1 is a sphere) swept by radius.
struct Capsule {
  Vec3 p0;
  Vec3 p1;
  double radius = 0.0;
};

// Upright capsule, the crowd's common case: a vertical core segment centred on (x, y, z) with
// half length half_height (>= 0). Kept as five scalars so the solver can store it as SoA.
struct UprightCapsule {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
  double half_height = 0.0;
  double radius = 0.0;
};

// Result of a pairwise query between shapes a and b.
//   distance: signed surface separation; negative = penetration depth.
//   normal:   unit vector from a toward b, i.e. the direction b must move to separate
//             (a must move along -normal). Always finite and unit length.
//   point_a / point_b: closest points on the core segments (not on the surfaces); the surface
//             points are point_a + normal * ra and point_b - normal * rb.
struct Contact {
  double distance = 0.0;
  Vec3 normal{1.0, 0.0, 0.0};
  Vec3 point_a;
  Vec3 point_b;
};

// The general form of an upright capsule (p0 below p1), with the exact same endpoint rounding the
// upright fast path uses, so both paths see identical inputs.
constexpr Capsule to_capsule(const UprightCapsule& u) {
  return Capsule{{u.x, u.y, u.z - u.half_height}, {u.x, u.y, u.z + u.half_height}, u.radius};
}

}  // namespace throng::geom
