// Exact penetration of an upright capsule into an upright box or cylinder.
//
// Both the upright capsule core and these shapes are products of a horizontal set and a z-interval
// (core: a point x [z_lo, z_hi]; box: a rotated rectangle x [lo, hi]; cylinder: a disc x [lo, hi]).
// The distance between two such products is sqrt(d_xy^2 + d_z^2), so the capsule's signed distance
// is that minus its radius. When the core itself reaches into the shape the capsule centre lies
// inside the shape grown by the core's half length in z; the way out is then the nearest face of
// that grown shape plus the radius: straight up, straight down, or sideways through the nearest
// side (which is exactly the minimum translation, since the grown shape is convex).
#include "scenery_closed_form.h"

#include <cmath>

namespace throng::geom::detail {
namespace {

// Relation of the core's xy point to a footprint.
struct Footprint {
  double outside = 0.0;  // distance from the point to the footprint (0 when inside or on it)
  double ox = 0.0;       // unit horizontal direction footprint -> point (when outside > 0)
  double oy = 0.0;
  double inside = 0.0;  // distance from the point to the footprint boundary (when inside)
  double ix = 1.0;      // unit horizontal direction of the nearest way out (when inside)
  double iy = 0.0;
};

SignedPenetration combine(const UprightCore& c, const Footprint& f, double lo, double hi) {
  double dz = 0.0;
  if (c.z_lo > hi) {
    dz = c.z_lo - hi;  // core above the shape
  } else if (lo > c.z_hi) {
    dz = c.z_hi - lo;  // core below the shape (negative)
  }
  const double core = std::sqrt(f.outside * f.outside + dz * dz);
  if (core > 0.0) {
    const double h = f.outside / core;
    return {c.radius - core, {f.ox * h, f.oy * h, dz / core}};
  }
  // The core reaches into the shape. Fixed preference on ties: up, sideways, down (stepping up
  // onto a ledge is the least surprising resolution for a character).
  SignedPenetration best{(hi - c.z_lo) + c.radius, {0.0, 0.0, 1.0}};
  const double side = f.inside + c.radius;
  if (side < best.depth) best = {side, {f.ix, f.iy, 0.0}};
  const double down = (c.z_hi - lo) + c.radius;
  if (down < best.depth) best = {down, {0.0, 0.0, -1.0}};
  return best;
}

}  // namespace

SignedPenetration upright_capsule_vs_box(const UprightCore& core, const BoxShape& box) {
  const double rx = core.x - box.centre.x;
  const double ry = core.y - box.centre.y;
  const double c = box.cos_yaw;
  const double s = box.sin_yaw;
  const double lx = rx * c + ry * s;  // point in the box frame
  const double ly = ry * c - rx * s;
  const double ex = std::fabs(lx) - box.half.x;  // > 0: outside that pair of faces
  const double ey = std::fabs(ly) - box.half.y;
  const double sx = lx < 0.0 ? -1.0 : 1.0;  // on the centre line, +u / +v (deterministic)
  const double sy = ly < 0.0 ? -1.0 : 1.0;

  Footprint f;
  if (ex > 0.0 || ey > 0.0) {
    const double qx = ex > 0.0 ? ex : 0.0;
    const double qy = ey > 0.0 ? ey : 0.0;
    f.outside = std::sqrt(qx * qx + qy * qy);
    const double ux = sx * qx / f.outside;  // local direction
    const double uy = sy * qy / f.outside;
    f.ox = ux * c - uy * s;
    f.oy = ux * s + uy * c;
  } else if (ex >= ey) {  // nearer to a +-u face (ties go to u)
    f.inside = -ex;
    f.ix = sx * c;
    f.iy = sx * s;
  } else {
    f.inside = -ey;
    f.ix = -sy * s;
    f.iy = sy * c;
  }
  return combine(core, f, box.centre.z - box.half.z, box.centre.z + box.half.z);
}

SignedPenetration upright_capsule_vs_cylinder(const UprightCore& core, const CylinderShape& cyl) {
  const double rx = core.x - cyl.centre.x;
  const double ry = core.y - cyl.centre.y;
  const double rho = std::sqrt(rx * rx + ry * ry);
  Footprint f;
  if (rho > cyl.radius) {
    f.outside = rho - cyl.radius;
    f.ox = rx / rho;
    f.oy = ry / rho;
  } else {
    f.inside = cyl.radius - rho;
    if (rho > 0.0) {  // on the axis every side is equally near: +x
      f.ix = rx / rho;
      f.iy = ry / rho;
    }
  }
  return combine(core, f, cyl.centre.z - cyl.half_height, cyl.centre.z + cyl.half_height);
}

}  // namespace throng::geom::detail
