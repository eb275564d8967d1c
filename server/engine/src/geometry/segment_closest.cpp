// Segment-segment closest points. See segment_closest.h for the contract.
//
// Work is done relative to p0 (w = q0 - p0) so that two characters 10 km from the origin get the
// same relative accuracy as two at the origin: only differences of nearby coordinates enter the
// arithmetic, and those are exact or nearly so.
#include "throng/geometry/segment_closest.h"

#include <algorithm>

#include "accurate_cross.h"

namespace throng::geom {
namespace {

double clamp01(double v) { return v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v); }

// Below this sine of the angle between the axes we treat them as parallel. With the accurate cross
// product the skew-line solve stays accurate far below this, and treating axes this close to
// parallel as parallel moves the distance by at most length * 1e-14, i.e. rounding level.
constexpr double kParallelSin = 1e-14;
constexpr double kAccurateCrossSin2 = 0.01;  // sin^2 of ~5.7 degrees

}  // namespace

SegmentClosest closest_points_segment_segment(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                              const Vec3& q1) {
  const Vec3 d1 = p1 - p0;
  const Vec3 d2 = q1 - q0;
  const Vec3 w = q0 - p0;
  const double a = dot(d1, d1);
  const double e = dot(d2, d2);
  const double wd1 = dot(w, d1);
  const double wd2 = dot(w, d2);

  double s = 0.0;
  double t = 0.0;
  if (a == 0.0 && e == 0.0) {
    // Two points: nothing to choose.
  } else if (a == 0.0) {
    t = clamp01(-wd2 / e);  // project p0 onto segment 2
  } else if (e == 0.0) {
    s = clamp01(wd1 / a);  // project q0 onto segment 1
  } else {
    const double b = dot(d1, d2);
    // The plain cross product is accurate to eps / sin(angle) relative; below ~6 degrees redo it
    // exactly (fma), see accurate_cross.h. The branch depends on the inputs only: deterministic.
    Vec3 n = cross(d1, d2);
    double nn = dot(n, n);
    if (nn < kAccurateCrossSin2 * a * e) {
      n = detail::accurate_cross(d1, d2);
      nn = dot(n, n);
    }
    if (nn > kParallelSin * kParallelSin * a * e) {
      // Skew lines: s of the line-line closest pair is ((w x d2) . n) / |n|^2 (the cross-product
      // form of Ericson's (bf - ce) / (ae - b^2), which cancels catastrophically when nearly
      // parallel). Then Ericson's clamp order: clamp s, best t for it, and if t had to be clamped,
      // best s for the clamped t. That order is exact for this convex quadratic (KKT holds at
      // exit).
      s = clamp01(dot(cross(w, d2), n) / nn);
      t = (b * s - wd2) / e;
      if (t < 0.0) {
        t = 0.0;
        s = clamp01(wd1 / a);
      } else if (t > 1.0) {
        t = 1.0;
        s = clamp01((wd1 + b) / a);
      }
    } else {
      // Parallel: the closest pair is not unique where the projections overlap. Take the middle of
      // the overlap (stable under small motions, and the natural point for side-by-side bodies);
      // otherwise the facing ends.
      const double u0 = wd1 / a;        // q0 projected on segment 1's parameter
      const double u1 = (wd1 + b) / a;  // q1 projected on segment 1's parameter
      const double lo = std::max(std::min(u0, u1), 0.0);
      const double hi = std::min(std::max(u0, u1), 1.0);
      if (lo <= hi) {
        s = 0.5 * (lo + hi);
        t = clamp01((b * s - wd2) / e);
      } else {
        s = std::max(u0, u1) < 0.0 ? 0.0 : 1.0;
        t = clamp01((b * s - wd2) / e);
        s = clamp01((wd1 + b * t) / a);
      }
    }
  }

  SegmentClosest r;
  r.s = s;
  r.t = t;
  r.point_1 = p0 + d1 * s;
  r.point_2 = q0 + d2 * t;
  r.delta = (w + d2 * t) - d1 * s;
  r.distance_squared = dot(r.delta, r.delta);
  r.scale = detail::abs_sum(d1) + detail::abs_sum(d2) + detail::abs_sum(w);
  return r;
}

}  // namespace throng::geom
