#pragma once
// Independent long-double reference for capsule_capsule, used only to validate the closed form.
//
// Independent on purpose: it does not use Ericson's clamp sequence. It enumerates every candidate
// for the minimum of the convex quadratic |P(s) - Q(t)|^2 over [0,1]^2 (the interior stationary
// point if it lies in the square, and the clamped minimiser on each of the four edges) and keeps
// the smallest, all in x87 extended precision (64-bit mantissa) with an fma-exact cross product.
#include <array>

#include "throng/geometry/capsule.h"

namespace throng::geom {

struct ReferenceContact {
  long double core_distance = 0.0L;     // distance between the core segments
  long double distance = 0.0L;          // core_distance - ra - rb
  bool normal_defined = false;          // false when the cores touch (core_distance == 0)
  std::array<long double, 3> normal{};  // (point_b - point_a) / core_distance, a -> b
  std::array<long double, 3> point_a{};
  std::array<long double, 3> point_b{};
  long double s = 0.0L;  // parameters of the closest points
  long double t = 0.0L;
};

ReferenceContact capsule_capsule_reference(const Capsule& a, const Capsule& b);

}  // namespace throng::geom
