// StaticScenery::first_hit_fraction: how far a fast mover may go along its displacement.
//
// Sampling + bisection rather than conservative advancement: conservative advancement needs a
// separation distance from every shape (the penetration queries here only give depths), and it
// crawls when a mover slides along a wall. Samples at most radius / 2 apart cannot step over any
// shape, even a zero-thickness triangle: crossing it means overlapping it over a stretch of at
// least the mover's diameter, which holds several samples. Bisection then pins the first touch.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "scenery_impl.h"

namespace throng::geom {
namespace {

// For shapes penetrated at the start: depth growth that counts as a hit. Exact closed forms need
// only rounding slack; FCL's depth (tilted movers vs boxes and cylinders) jitters between nearby
// poses, so a tilted mover resting against a wall may still slide along it. Shapes not penetrated
// at the start are hit at any depth > 0, exactly query()'s criterion, so the pose returned never
// shows up in query().
constexpr double kSkinExact = 1e-9;
constexpr double kSkinFcl = 1e-6;
constexpr double kMinStep = 1e-3;          // metres; the step for very thin movers
constexpr long kMaxSamples = 1L << 16;     // cost cap for absurd displacements
constexpr double kBisectTolerance = 1e-9;  // metres of travel

Capsule moved(const Capsule& c, const Vec3& d, double f) {
  const Vec3 step = d * f;
  return {c.p0 + step, c.p1 + step, c.radius};
}

Aabb merge(const Aabb& a, const Aabb& b) {
  return {{std::min(a.lo.x, b.lo.x), std::min(a.lo.y, b.lo.y), std::min(a.lo.z, b.lo.z)},
          {std::max(a.hi.x, b.hi.x), std::max(a.hi.y, b.hi.y), std::max(a.hi.z, b.hi.z)}};
}

}  // namespace

double StaticScenery::first_hit_fraction(const Capsule& mover, Vec3 displacement) const {
  impl_->require_built("first_hit_fraction");
  detail::validate_mover(mover, "StaticScenery::first_hit_fraction");
  if (!is_finite(displacement)) {
    throw std::invalid_argument("StaticScenery::first_hit_fraction: displacement must be finite");
  }
  const double travel = length(displacement);
  if (travel == 0.0) return 1.0;

  detail::QueryScratch& s = detail::query_scratch();
  impl_->gather(
      merge(detail::capsule_aabb(mover), detail::capsule_aabb(moved(mover, displacement, 1.0))), s);
  if (s.candidates.empty()) return 1.0;

  // Translation keeps an upright mover upright (x and y shift by the same amount).
  const bool upright = detail::is_upright(mover);
  // Penetration already present at the start: only going deeper counts as a hit.
  s.baseline.clear();
  for (const std::uint32_t i : s.candidates) {
    const double d = impl_->penetration(i, mover, upright, s).depth;
    s.baseline.push_back(d > 0.0 ? d : 0.0);
  }
  auto hits = [&](double f) {
    const Capsule c = moved(mover, displacement, f);
    for (std::size_t k = 0; k < s.candidates.size(); ++k) {
      const std::uint32_t i = s.candidates[k];
      double limit = 0.0;
      if (s.baseline[k] > 0.0) {
        const bool exact = upright || impl_->shapes[i].kind == ShapeKind::kMesh;
        limit = s.baseline[k] + (exact ? kSkinExact : kSkinFcl);
      }
      if (impl_->penetration(i, c, upright, s).depth > limit) return true;
    }
    return false;
  };

  const double step = std::max(0.5 * mover.radius, kMinStep);
  // Clamped before the conversion: a travel beyond long's range must not be converted (UB).
  const long samples = static_cast<long>(std::clamp(std::ceil(travel / step), 1.0, static_cast<double>(kMaxSamples)));
  double free_f = 0.0;
  for (long k = 1; k <= samples; ++k) {
    const double f = static_cast<double>(k) / static_cast<double>(samples);
    if (!hits(f)) {
      free_f = f;
      continue;
    }
    double lo = free_f;  // known free
    double hi = f;       // known hit
    while ((hi - lo) * travel > kBisectTolerance) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;  // no representable midpoint left
      (hits(mid) ? hi : lo) = mid;
    }
    return lo;
  }
  return 1.0;
}

}  // namespace throng::geom
