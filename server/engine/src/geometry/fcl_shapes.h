#pragma once
// Private bridge between throng geometry and FCL: conversions and the FCL pose of a capsule.
// Only .cpp files under src/geometry include this (FCL is a PRIVATE dependency of the engine).
#include <fcl/geometry/shape/capsule.h>
#include <fcl/math/constants.h>
#include <fcl/math/geometry.h>

#include <Eigen/Geometry>

#include "throng/core/vec3.h"
#include "throng/geometry/capsule.h"

namespace throng::geom::detail {

inline fcl::Vector3d to_fcl(const Vec3& v) { return fcl::Vector3d(v.x, v.y, v.z); }
inline Vec3 from_fcl(const fcl::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// FCL capsules (and cylinders) lie along their local z axis, centred on the origin: the pose puts
// the centre at the segment midpoint and turns +z onto p1 - p0. Zero-length segments keep the
// identity rotation.
inline fcl::Transform3d capsule_pose(const Capsule& c) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  const fcl::Vector3d p0 = to_fcl(c.p0);
  const fcl::Vector3d p1 = to_fcl(c.p1);
  tf.translation() = 0.5 * (p0 + p1);
  const fcl::Vector3d axis = p1 - p0;
  const double len = axis.norm();
  if (len > 0.0) {
    tf.linear() =
        Eigen::Quaterniond::FromTwoVectors(fcl::Vector3d::UnitZ(), axis / len).toRotationMatrix();
  }
  return tf;
}

inline double capsule_length(const Capsule& c) { return length(c.p1 - c.p0); }

}  // namespace throng::geom::detail
