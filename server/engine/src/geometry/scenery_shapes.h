#pragma once
// Private plain-data descriptions of the fixed shapes, shared by the closed forms, the ground
// query and the FCL wrapper. No FCL here.
#include <array>
#include <cstdint>
#include <vector>

#include "throng/core/vec3.h"

namespace throng::geom::detail {

struct BoxShape {
  Vec3 centre;
  Vec3 half;       // half extents along the local axes u, v and world z
  double cos_yaw;  // u = (cos, sin, 0), v = (-sin, cos, 0)
  double sin_yaw;
};

struct CylinderShape {
  Vec3 centre;
  double radius;
  double half_height;
};

struct MeshShape {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

// The core segment of an upright capsule as an xy point and a z interval.
struct UprightCore {
  double x, y;
  double z_lo, z_hi;
  double radius;
};

// Signed penetration: depth > 0 penetrating (move `normal` by depth to get out); depth <= 0 means
// separated by -depth, with normal pointing from the shape towards the mover.
struct SignedPenetration {
  double depth;
  Vec3 normal;
};

}  // namespace throng::geom::detail
