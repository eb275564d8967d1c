// Tilted mover vs upright box / cylinder (no product structure, so no closed form like the
// upright case).
//
// Shallow contact (the core segment outside the shape, the normal case): the squared distance from
// a point moving along the core to a convex shape is a convex function of the segment parameter,
// so bisecting on the sign of its derivative, using the exact point-to-shape closest point, finds
// the core distance and witness points to rounding level in <= 80 cheap steps;
// depth = radius - distance along the closest-point direction.
// Not FCL's GJK: on segment-vs-box distances FCL's own GJK (GST_INDEP) is wrong in a fraction of
// random poses whatever the tolerance, and libccd's GJK is off by millimetres at a cylinder's rim
// at FCL's default tolerance (figures: docs/design/solver.md).
//
// Deep contact (the core touches or enters the shape): fcl::collide with libccd MPR, whose
// push-out is valid but not necessarily the shortest (see the contact validation report). FCL's
// GJK/EPA (GST_INDEP) is not used: it reports negative depths and mis-rotated normals.
#include <fcl/narrowphase/collision.h>

#include <algorithm>
#include <cmath>

#include "fcl_shapes.h"
#include "scenery_impl.h"

namespace throng::geom::detail {
namespace {

Vec3 closest_on_box(const Vec3& p, const BoxShape& b) {
  const Vec3 r = p - b.centre;
  const double lx = r.x * b.cos_yaw + r.y * b.sin_yaw;
  const double ly = r.y * b.cos_yaw - r.x * b.sin_yaw;
  const double cx = std::clamp(lx, -b.half.x, b.half.x);
  const double cy = std::clamp(ly, -b.half.y, b.half.y);
  const double cz = std::clamp(r.z, -b.half.z, b.half.z);
  // Move p by the clamping correction (rotated back), so an inside point is returned unchanged.
  const double ex = cx - lx;
  const double ey = cy - ly;
  return {p.x + ex * b.cos_yaw - ey * b.sin_yaw, p.y + ex * b.sin_yaw + ey * b.cos_yaw,
          p.z + (cz - r.z)};
}

Vec3 closest_on_cylinder(const Vec3& p, const CylinderShape& c) {
  const double rx = p.x - c.centre.x;
  const double ry = p.y - c.centre.y;
  const double rho = std::sqrt(rx * rx + ry * ry);
  Vec3 q = p;
  if (rho > c.radius) {
    const double k = c.radius / rho;
    q.x = c.centre.x + rx * k;
    q.y = c.centre.y + ry * k;
  }
  q.z = std::clamp(p.z, c.centre.z - c.half_height, c.centre.z + c.half_height);
  return q;
}

struct CoreClosest {
  Vec3 on_core;
  Vec3 on_shape;
  double distance;
};

// Minimum over t in [0, 1] of |P(t) - closest(P(t))|. The squared distance to a convex set is
// convex and differentiable along the segment, with derivative 2 (P - closest(P)) . d; bisecting
// on the sign of that derivative pins t to full precision (a golden-section search on the value
// only gets sqrt(eps) in t, i.e. ~1e-8 rad in the normal).
template <typename Closest>
CoreClosest core_distance(const Capsule& m, Closest closest) {
  const Vec3 d = m.p1 - m.p0;
  auto at = [&](double t) {
    const Vec3 p = m.p0 + d * t;
    return CoreClosest{p, closest(p), 0.0};
  };
  auto slope = [&](const CoreClosest& c) { return dot(c.on_core - c.on_shape, d); };
  CoreClosest best = at(0.0);
  if (!(d == Vec3{}) && slope(best) < 0.0) {  // distance still falling at t = 0
    const CoreClosest end = at(1.0);
    if (slope(end) <= 0.0) {
      best = end;  // still falling (or flat) at t = 1
    } else {
      double lo = 0.0;
      double hi = 1.0;
      for (int i = 0; i < 80; ++i) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;
        (slope(at(mid)) < 0.0 ? lo : hi) = mid;
      }
      best = at(0.5 * (lo + hi));
    }
  }
  best.distance = length(best.on_core - best.on_shape);
  return best;
}

SignedPenetration deep_contact(const ShapeRecord& shape, const Capsule& mover, QueryScratch& s) {
  const fcl::Capsuled capsule(mover.radius, capsule_length(mover));  // no allocation
  const fcl::Transform3d pose = capsule_pose(mover);
  s.request.enable_contact = true;
  s.request.gjk_solver_type = fcl::GST_LIBCCD;
  s.request.num_max_contacts = 1;
  s.result.clear();  // keeps the contact vector's capacity
  fcl::collide(&capsule, pose, shape.geometry.get(), shape.pose, s.request, s.result);
  if (s.result.numContacts() == 0) return {0.0, {0.0, 0.0, 1.0}};
  const fcl::Contactd& c = s.result.getContact(0);
  // FCL's normal points from its o1 (our capsule) to its o2: out of the shape is the opposite.
  const fcl::Vector3d out = c.o1 == &capsule ? fcl::Vector3d(-c.normal) : c.normal;
  const double n = out.norm();
  if (!(c.penetration_depth > 0.0) || !(n > 0.0) || !out.allFinite()) {
    return {0.0, {0.0, 0.0, 1.0}};
  }
  return {c.penetration_depth, from_fcl(out / n)};
}

}  // namespace

SignedPenetration tilted_penetration(const ShapeRecord& shape, const BoxShape* box,
                                     const CylinderShape* cylinder, const Capsule& mover,
                                     QueryScratch& s) {
  const CoreClosest cc =
      box ? core_distance(mover, [box](const Vec3& p) { return closest_on_box(p, *box); })
          : core_distance(mover,
                          [cylinder](const Vec3& p) { return closest_on_cylinder(p, *cylinder); });
  // Below this the witness direction is rounding noise (or the core is inside): deep contact.
  const double noise =
      64.0 * 2.220446049250313e-16 *
      (1.0 + std::fabs(cc.on_core.x) + std::fabs(cc.on_core.y) + std::fabs(cc.on_core.z));
  if (cc.distance > noise) {
    const Vec3 e = cc.on_core - cc.on_shape;
    return {mover.radius - cc.distance, {e.x / cc.distance, e.y / cc.distance, e.z / cc.distance}};
  }
  return deep_contact(shape, mover, s);
}

}  // namespace throng::geom::detail
