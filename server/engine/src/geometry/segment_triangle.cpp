// Segment-triangle closest points; see segment_triangle.h.
#include "segment_triangle.h"

#include <cmath>

#include "accurate_cross.h"
#include "throng/geometry/segment_closest.h"

namespace throng::geom::detail {

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Voronoi regions of the vertices, then the edges, then the face.
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 ap = p - a;
  const double d1 = dot(ab, ap);
  const double d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp);
  const double d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp);
  const double d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  }
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

SegmentTriangleClosest closest_segment_triangle(const Vec3& p0, const Vec3& p1, const Vec3& a,
                                                const Vec3& b, const Vec3& c) {
  SegmentTriangleClosest r;
  r.scale = abs_sum(p1 - p0) + abs_sum(p0 - a) + abs_sum(b - a) + abs_sum(c - a);

  // Piercing: endpoints strictly on opposite sides of the plane, crossing point inside.
  const Vec3 n = accurate_cross(b - a, c - a);
  const double s0 = dot(p0 - a, n);
  const double s1 = dot(p1 - a, n);
  if ((s0 < 0.0 && s1 > 0.0) || (s0 > 0.0 && s1 < 0.0)) {
    const Vec3 x = p0 + (p1 - p0) * (s0 / (s0 - s1));
    const double ea = dot(cross(b - a, x - a), n);
    const double eb = dot(cross(c - b, x - b), n);
    const double ec = dot(cross(a - c, x - c), n);
    if (ea >= 0.0 && eb >= 0.0 && ec >= 0.0) {
      r.on_segment = r.on_triangle = x;
      r.distance = 0.0;
      r.pierces = true;
      return r;
    }
  }

  // Otherwise the five boundary candidates; strict < keeps the first of equal ones.
  bool first = true;
  double best2 = 0.0;
  auto consider = [&](const Vec3& on_seg, const Vec3& on_tri) {
    const Vec3 d = on_seg - on_tri;
    const double d2 = dot(d, d);
    if (first || d2 < best2) {
      first = false;
      best2 = d2;
      r.on_segment = on_seg;
      r.on_triangle = on_tri;
    }
  };
  consider(p0, closest_point_on_triangle(p0, a, b, c));
  consider(p1, closest_point_on_triangle(p1, a, b, c));
  const Vec3* const corners[3] = {&a, &b, &c};
  for (int e = 0; e < 3; ++e) {
    const SegmentClosest sc =
        closest_points_segment_segment(p0, p1, *corners[e], *corners[(e + 1) % 3]);
    consider(sc.point_1, sc.point_2);
  }
  r.distance = std::sqrt(best2);
  return r;
}

}  // namespace throng::geom::detail
