#pragma once
// Exact closest points between a segment and a triangle (private; used for mesh contacts).
#include "throng/core/vec3.h"

namespace throng::geom::detail {

struct SegmentTriangleClosest {
  Vec3 on_segment;
  Vec3 on_triangle;
  double distance = 0.0;
  bool pierces = false;  // the segment passes through the triangle's interior (distance 0)
  double scale = 0.0;    // size of the configuration, for noise thresholds
};

// If the segment does not meet the triangle, the closest pair has a segment endpoint against the
// triangle or the segment against one of its edges, so those five candidates are exact; a
// separate plane test catches segments that pierce the interior.
SegmentTriangleClosest closest_segment_triangle(const Vec3& p0, const Vec3& p1, const Vec3& a,
                                                const Vec3& b, const Vec3& c);

// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace throng::geom::detail
