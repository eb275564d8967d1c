#pragma once
// Exact contact between upright capsules in closed form: a second derivation that the capsule
// contact tests hold capsule_capsule to (nothing outside the tests uses it).
//
// Two vertical segments are a product of a horizontal point and a z-interval each, so the distance
// between the cores is sqrt(dxy^2 + gap_z^2) with gap_z the gap between the z-intervals (0 when
// they overlap). This is the same value capsule_capsule computes for the same shapes, without the
// general segment solve.
#include <algorithm>
#include <cmath>

#include "throng/geometry/capsule.h"
#include "throng/geometry/capsule_contact.h"

namespace throng::geom {

// Gap between the core z-intervals (>= 0; 0 when they overlap).
inline double vertical_gap(const UprightCapsule& a, const UprightCapsule& b) {
  const double a_lo = a.z - a.half_height;
  const double a_hi = a.z + a.half_height;
  const double b_lo = b.z - b.half_height;
  const double b_hi = b.z + b.half_height;
  if (b_lo > a_hi) return b_lo - a_hi;
  if (a_lo > b_hi) return a_lo - b_hi;
  return 0.0;
}

// Horizontal axis distance at which two upright capsules whose cores are vertical_gap apart in z
// just touch: sqrt(rs^2 - gap^2), or 0 when the gap alone separates them. Written as
// sqrt((rs - g)(rs + g)), which does not cancel when g is close to rs.
inline double required_horizontal_separation(double vertical_gap_z, double radius_sum) {
  const double g = std::fabs(vertical_gap_z);
  if (g >= radius_sum) return 0.0;
  return std::sqrt((radius_sum - g) * (radius_sum + g));
}

inline double required_horizontal_separation(const UprightCapsule& a, const UprightCapsule& b) {
  return required_horizontal_separation(vertical_gap(a, b), a.radius + b.radius);
}

// Same contract as capsule_capsule (capsule.h): signed distance, unit normal a -> b, core points.
// Where the z-intervals overlap the core points sit at the middle of the overlap (as the general
// function does for parallel axes). Coaxial overlapping cores get the +x fallback normal.
inline Contact upright_capsule_capsule(const UprightCapsule& a, const UprightCapsule& b) {
  const double dx = b.x - a.x;
  const double dy = b.y - a.y;
  const double a_lo = a.z - a.half_height;
  const double a_hi = a.z + a.half_height;
  const double b_lo = b.z - b.half_height;
  const double b_hi = b.z + b.half_height;

  double dz = 0.0;
  double za = 0.0;
  double zb = 0.0;
  if (b_lo > a_hi) {  // b entirely above a
    dz = b_lo - a_hi;
    za = a_hi;
    zb = b_lo;
  } else if (a_lo > b_hi) {  // b entirely below a
    dz = b_hi - a_lo;
    za = a_lo;
    zb = b_hi;
  } else {
    za = zb = 0.5 * (std::max(a_lo, b_lo) + std::min(a_hi, b_hi));
  }

  const double core = std::sqrt(dx * dx + dy * dy + dz * dz);
  Contact c;
  c.distance = core - (a.radius + b.radius);
  c.point_a = {a.x, a.y, za};
  c.point_b = {b.x, b.y, zb};
  // Same noise threshold and scale as the general path (segment lengths + |b.p0 - a.p0|_1).
  const double scale =
      (a_hi - a_lo) + (b_hi - b_lo) + std::fabs(dx) + std::fabs(dy) + std::fabs(b_lo - a_lo);
  if (core > kCoreTouchRelTol * scale) {
    c.normal = {dx / core, dy / core, dz / core};
  } else {
    c.normal = {1.0, 0.0, 0.0};
  }
  return c;
}

}  // namespace throng::geom
