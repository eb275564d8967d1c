// Capsule pair families for validation. Every construction is written so the property the
// family is named after holds exactly, or up to the rounding of a handful of operations.
#include "throng/geometry/capsule_pair_generator.h"

#include <cmath>

namespace throng::geom {

std::string_view family_name(PairFamily f) {
  switch (f) {
    case PairFamily::kGeneric: return "generic";
    case PairFamily::kParallel: return "parallel";
    case PairFamily::kNearParallel: return "near-parallel";
    case PairFamily::kCrossing: return "crossing";
    case PairFamily::kSpheres: return "spheres";
    case PairFamily::kTouching: return "touching";
    case PairFamily::kDeepPenetration: return "deep";
    case PairFamily::kFarFromOrigin: return "far-10km";
    case PairFamily::kCount: break;
  }
  return "?";
}

double CapsulePairGenerator::uniform01() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }

double CapsulePairGenerator::uniform(double lo, double hi) { return lo + (hi - lo) * uniform01(); }

Vec3 CapsulePairGenerator::unit_vector() {
  for (;;) {  // rejection from the cube: uniform direction, deterministic given the stream
    const Vec3 v{uniform(-1.0, 1.0), uniform(-1.0, 1.0), uniform(-1.0, 1.0)};
    const double n2 = dot(v, v);
    if (n2 > 1e-4 && n2 <= 1.0) return v * (1.0 / std::sqrt(n2));
  }
}

Vec3 CapsulePairGenerator::unit_perpendicular(const Vec3& u) {
  for (;;) {
    const Vec3 r = unit_vector();
    const Vec3 p = r - u * dot(r, u);
    const double n2 = dot(p, p);
    if (n2 > 1e-4) {
      const Vec3 q = p * (1.0 / std::sqrt(n2));
      return q - u * dot(q, u);  // one more projection: perpendicular to rounding level
    }
  }
}

Capsule CapsulePairGenerator::random_capsule(const Vec3& centre) {
  // One draw per statement: the order of evaluation of operands is unspecified in C++, and the
  // pairs must not depend on the compiler.
  const Vec3 direction = unit_vector();
  const Vec3 axis = direction * uniform(0.05, 1.0);  // half axis
  return {centre - axis, centre + axis, uniform(0.05, 0.6)};
}

CapsulePair CapsulePairGenerator::next(PairFamily family) {
  CapsulePair p;
  p.family = family;
  auto cube = [&](double h) { return Vec3{uniform(-h, h), uniform(-h, h), uniform(-h, h)}; };
  switch (family) {
    case PairFamily::kGeneric:
    case PairFamily::kCount: {
      p.a = random_capsule(cube(1.0));
      p.b = random_capsule(cube(1.0));
      break;
    }
    case PairFamily::kFarFromOrigin: {
      const double phi = uniform(0.0, 6.283185307179586);
      const Vec3 far{1.0e4 * std::cos(phi), 1.0e4 * std::sin(phi), uniform(0.0, 30.0)};
      p.a = random_capsule(far + cube(1.0));
      p.b = random_capsule(far + cube(1.0));
      break;
    }
    case PairFamily::kParallel: {
      p.a = random_capsule(cube(1.0));
      const Vec3 d1 = p.a.p1 - p.a.p0;
      // Power-of-two scale factors keep d2 = k * d1 exactly parallel in floating point.
      static constexpr double kScale[4] = {1.0, -1.0, 0.5, -2.0};
      const double k = kScale[static_cast<int>(uniform01() * 4.0) & 3];
      const Vec3 u = d1 * (1.0 / length(d1));
      const double lateral = uniform01() < 0.25 ? 0.0 : uniform(0.0, 1.5);  // 1/4 collinear
      const double along = uniform(-2.0, 2.0);
      const Vec3 side = unit_perpendicular(u);
      const Vec3 start = p.a.p0 + u * along + side * lateral;
      p.b = {start, start + d1 * k, uniform(0.05, 0.6)};
      break;
    }
    case PairFamily::kNearParallel: {
      p.a = random_capsule(cube(1.0));
      const Vec3 d1 = p.a.p1 - p.a.p0;
      const Vec3 u = d1 * (1.0 / length(d1));
      const double angle = std::pow(10.0, uniform(-12.0, -3.0));
      const Vec3 v = u + unit_perpendicular(u) * angle;  // direction of b, `angle` off u
      const double len = uniform(0.1, 2.0);
      if (uniform01() < 0.5) {
        // Cores (nearly) crossing at a tiny angle: b passes through a point of a's core.
        const Vec3 x = p.a.p0 + d1 * uniform(0.0, 1.0);
        const double before = uniform(0.0, 1.0) * len;
        p.b = {x - v * before, x + v * (len - before), uniform(0.05, 0.6)};
      } else {
        const double along = uniform(-1.0, 1.0);
        const Vec3 side = unit_perpendicular(u);
        const double offset = uniform(0.0, 1.2);
        const Vec3 start = p.a.p0 + u * along + side * offset;
        p.b = {start, start + v * len, uniform(0.05, 0.6)};
      }
      break;
    }
    case PairFamily::kCrossing: {
      const Vec3 x = cube(1.0);
      const Vec3 u = unit_vector();
      const Vec3 v = unit_vector();
      p.a = {x - u * uniform(0.0, 1.0), x + u * uniform(0.0, 1.0), uniform(0.05, 0.6)};
      p.b = {x - v * uniform(0.0, 1.0), x + v * uniform(0.0, 1.0), uniform(0.05, 0.6)};
      break;
    }
    case PairFamily::kSpheres: {
      const double pick = uniform01();
      p.a = random_capsule(cube(1.0));
      p.b = random_capsule(cube(1.0));
      if (pick < 0.5) p.b.p1 = p.b.p0;            // sphere vs capsule
      if (pick >= 0.25) p.a.p1 = p.a.p0;          // capsule vs sphere, or sphere vs sphere
      if (pick >= 0.9) p.b.p0 = p.b.p1 = p.a.p0;  // coincident centres
      break;
    }
    case PairFamily::kTouching:
    case PairFamily::kDeepPenetration: {
      p.a = random_capsule(cube(1.0));
      const double rb = uniform(0.05, 0.6);
      const double gap_scale = family == PairFamily::kTouching ? 1.0 : uniform(0.02, 0.6);
      const double gap = (p.a.radius + rb) * gap_scale;  // core distance
      const Vec3 d1 = p.a.p1 - p.a.p0;
      const Vec3 u = d1 * (1.0 / length(d1));
      if (uniform01() < 0.7) {
        // Side contact: closest points interior to both cores, joined along n perpendicular to
        // both axes, so they are the exact closest pair (a stationary point of a convex function).
        const Vec3 pa = p.a.p0 + d1 * uniform(0.1, 0.9);
        const Vec3 n = unit_perpendicular(u);
        const Vec3 pb = pa + n * gap;
        const Vec3 v = unit_perpendicular(n);
        const double len = uniform(0.1, 2.0);
        const double before = uniform(0.1, 0.9) * len;
        p.b = {pb - v * before, pb + v * (len - before), rb};
      } else {
        // End-cap contact: a's end p1 and b's end q0 joined along n, with both cores receding
        // from the slab between them (n.d1 >= 0, n.d2 >= 0), so they are the closest pair.
        Vec3 n = unit_vector();
        if (dot(n, u) < 0.0) n = -n;
        const Vec3 q0 = p.a.p1 + n * gap;
        Vec3 v = unit_vector();
        if (dot(v, n) < 0.0) v = -v;
        p.b = {q0, q0 + v * uniform(0.0, 2.0), rb};
      }
      break;
    }
  }
  return p;
}

}  // namespace throng::geom
