// General capsule-capsule contact: segment closest points minus radii, plus the deterministic
// normal for touching cores.
#include "throng/geometry/capsule_contact.h"

#include <cmath>

#include "accurate_cross.h"
#include "throng/geometry/segment_closest.h"

namespace throng::geom {
namespace {

// Axes closer to parallel than this (sine of the angle) have no well-conditioned common
// perpendicular; they separate sideways like parallel axes.
constexpr double kCrossingSin = 1e-6;

Vec3 divided(const Vec3& v, double d) { return {v.x / d, v.y / d, v.z / d}; }

}  // namespace

Vec3 touching_cores_normal(const Vec3& axis_a, const Vec3& axis_b, const Vec3& centre_offset) {
  const double aa = dot(axis_a, axis_a);
  const double bb = dot(axis_b, axis_b);
  const Vec3 n = detail::accurate_cross(axis_a, axis_b);
  const double nn = dot(n, n);
  if (aa > 0.0 && bb > 0.0 && nn > kCrossingSin * kCrossingSin * aa * bb) {
    Vec3 u = divided(n, std::sqrt(nn));
    if (dot(u, centre_offset) < 0.0) u = -u;
    return u;
  }
  const Vec3& axis = aa >= bb ? axis_a : axis_b;
  // z x axis: horizontal and perpendicular to the axis. Zero when the axis is vertical (or zero).
  Vec3 h{-axis.y, axis.x, 0.0};
  const double hh = h.x * h.x + h.y * h.y;
  if (!(hh > 1e-24 * dot(axis, axis))) return {1.0, 0.0, 0.0};  // vertical axis or points
  h = divided(h, std::sqrt(hh));
  if (h.x < 0.0 || (h.x == 0.0 && h.y < 0.0)) h = -h;
  h.x += 0.0;  // normalise a -0.0 component to +0.0 so outputs are bit-identical
  h.y += 0.0;
  return h;
}

Contact capsule_capsule(const Capsule& a, const Capsule& b) {
  const SegmentClosest sc = closest_points_segment_segment(a.p0, a.p1, b.p0, b.p1);
  const double core = std::sqrt(sc.distance_squared);
  Contact c;
  c.distance = core - (a.radius + b.radius);
  c.point_a = sc.point_1;
  c.point_b = sc.point_2;
  if (core > kCoreTouchRelTol * sc.scale) {
    c.normal = divided(sc.delta, core);
  } else {
    const Vec3 axis_a = a.p1 - a.p0;
    const Vec3 axis_b = b.p1 - b.p0;
    const Vec3 centre_offset = (b.p0 - a.p0) + (axis_b - axis_a) * 0.5;
    c.normal = touching_cores_normal(axis_a, axis_b, centre_offset);
  }
  return c;
}

}  // namespace throng::geom
