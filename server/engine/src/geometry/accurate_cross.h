#pragma once
// Cross product accurate to ~1 ulp per component, even when the inputs are nearly parallel.
//
// Why: the closest-point parameter of two skew lines divides by |d1 x d2|^2. A plain cross product
// of nearly parallel vectors loses almost all its digits to cancellation (relative error
// eps / sin(angle)), which feeds an error of eps / sin^2(angle) into the parameter and up to
// 1e-8 m into the distance for axes crossing at 1e-8 rad. Kahan's difference-of-products with an
// explicit fma keeps the cross product exact to an ulp, so the error drops to what the input
// rounding already implies. std::fma is correctly rounded by IEEE 754, so this is deterministic
// (it is an explicit operation, unaffected by -ffp-contract=off).
#include <cmath>

#include "throng/core/vec3.h"

namespace throng::geom::detail {

// a*b - c*d with at most 1.5 ulp error (Kahan / Jeannerod-Louvet-Muller).
inline double diff_of_products(double a, double b, double c, double d) {
  const double cd = c * d;
  const double err = std::fma(-c, d, cd);  // exact rounding error of c*d
  const double dop = std::fma(a, b, -cd);
  return dop + err;
}

inline Vec3 accurate_cross(const Vec3& a, const Vec3& b) {
  return {diff_of_products(a.y, b.z, a.z, b.y), diff_of_products(a.z, b.x, a.x, b.z),
          diff_of_products(a.x, b.y, a.y, b.x)};
}

inline double abs_sum(const Vec3& a) { return std::fabs(a.x) + std::fabs(a.y) + std::fabs(a.z); }

}  // namespace throng::geom::detail
