#pragma once
// Reproducible random capsule pairs in named families, for validating the contact code (tests,
// the validation report and the bench all draw from here so their figures are comparable).
//
// Reproducible across compilers and standard libraries: std::mt19937_64's sequence is fixed by
// the standard, but std::uniform_real_distribution's mapping is not, so we map bits ourselves.
// (The few libm calls in the constructions, cos / sin / pow, are the only platform dependence.)
#include <cstdint>
#include <random>
#include <string_view>

#include "throng/geometry/capsule.h"

namespace throng::geom {

enum class PairFamily : std::uint8_t {
  kGeneric,          // random poses in a 4 m cube, mixed separation/penetration
  kParallel,         // axes exactly parallel (or anti-parallel), incl. collinear overlapping cores
  kNearParallel,     // axes 1e-12..1e-3 rad apart, half of them with (nearly) crossing cores
  kCrossing,         // core segments intersect (core distance 0 up to rounding)
  kSpheres,          // one or both axes of zero length
  kTouching,         // surface distance exactly 0 by construction (side and end-cap contacts)
  kDeepPenetration,  // core distance 2%..60% of the radius sum
  kFarFromOrigin,    // generic pairs 10 km from the origin
  kCount
};

std::string_view family_name(PairFamily f);

struct CapsulePair {
  Capsule a;
  Capsule b;
  PairFamily family = PairFamily::kGeneric;
};

class CapsulePairGenerator {
 public:
  explicit CapsulePairGenerator(std::uint64_t seed) : rng_(seed) {}

  CapsulePair next(PairFamily family);

  double uniform01();                         // [0, 1), 53 random bits
  double uniform(double lo, double hi);       // [lo, hi)
  Vec3 unit_vector();                         // uniform on the sphere
  Vec3 unit_perpendicular(const Vec3& unit);  // uniform among unit vectors perpendicular to unit

 private:
  Capsule random_capsule(const Vec3& centre);
  std::mt19937_64 rng_;
};

}  // namespace throng::geom
