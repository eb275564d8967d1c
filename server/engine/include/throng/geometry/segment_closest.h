#pragma once
// Closest points between two segments (Ericson, Real-Time Collision Detection, 5.1.9), hardened for
// the cases a crowd produces all the time: parallel axes (two upright characters), zero-length
// axes (spheres), crossing axes and coordinates kilometres from the origin.
#include "throng/core/vec3.h"

namespace throng::geom {

struct SegmentClosest {
  double s = 0.0;  // parameter on segment 1: point_1 = p0 + s * (p1 - p0), s in [0, 1]
  double t = 0.0;  // parameter on segment 2: point_2 = q0 + t * (q1 - q0), t in [0, 1]
  Vec3 point_1;    // closest point on segment 1 (world coordinates)
  Vec3 point_2;    // closest point on segment 2 (world coordinates)
  Vec3 delta;      // point_2 - point_1, computed relative to p0 so it keeps full precision
                   // far from the origin (use this, not point_2 - point_1)
  double distance_squared = 0.0;  // |delta|^2
  double scale = 0.0;  // |p1-p0|_1 + |q1-q0|_1 + |q0-p0|_1: the size rounding errors scale with
};

// Deterministic for identical inputs. When the segments are parallel and their projections
// overlap, the closest pair is not unique; the middle of the overlap is returned (the natural
// contact point for two side-by-side characters). Inputs must be finite.
SegmentClosest closest_points_segment_segment(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                              const Vec3& q1);

}  // namespace throng::geom
