#pragma once
// Exact capsule-capsule contact in double precision (general orientation).
#include <cfloat>

#include "throng/geometry/capsule.h"

namespace throng::geom {

// Core distances at or below kCoreTouchRelTol * (sum of the segment and offset sizes) are rounding
// noise: the direction of the difference vector means nothing there, so the deterministic
// touching-cores normal is used instead. 64 ulps is comfortably above the noise of the solve.
inline constexpr double kCoreTouchRelTol = 64.0 * DBL_EPSILON;

// Signed distance, normal (a -> b) and core closest points. Never returns a NaN or non-unit normal
// for finite inputs. Deterministic: the same inputs give bit-identical outputs.
Contact capsule_capsule(const Capsule& a, const Capsule& b);

// The normal used when the cores touch or cross (no direction from the point difference):
//  * axes not parallel: the common perpendicular axis_a x axis_b, which is exactly the direction
//    of least separation for crossing segments; oriented towards b's centre
//    (centre_offset = centre_b - centre_a), keeping the axis_a x axis_b sign on an exact tie,
//    so swapping a and b flips the normal;
//  * parallel axes or points: a horizontal direction perpendicular to the longer axis, with
//    positive x (or positive y if x is 0); +x when that axis is vertical or both are points.
// Matches upright_capsule_capsule's fallback (+x) for coaxial upright capsules.
Vec3 touching_cores_normal(const Vec3& axis_a, const Vec3& axis_b, const Vec3& centre_offset);

}  // namespace throng::geom
