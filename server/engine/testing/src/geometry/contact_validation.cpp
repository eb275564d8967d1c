// Runs the capsule contact validation: closed form vs long-double reference vs FCL 0.7.
// The formatting of the results lives in validation_report.cpp.
#include "throng/geometry/contact_validation.h"

#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "geometry/fcl_shapes.h"
#include "throng/geometry/capsule_contact.h"
#include "throng/geometry/contact_reference.h"

namespace throng::geom {
namespace {

using L = long double;

struct Samples {
  std::vector<double> values;
  void add(double v) { values.push_back(v); }
  void append(const Samples& o) { values.insert(values.end(), o.values.begin(), o.values.end()); }
  ErrorStats stats() const {
    ErrorStats s;
    s.count = values.size();
    if (values.empty()) return s;
    std::vector<double> v = values;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    s.max = v.back();
    s.median = v[(n - 1) / 2];
    s.p99 = v[static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(n))) - 1];
    return s;
  }
};

struct CollideAcc {
  FclCollideStats stats;
  Samples depth;
  Samples abs_depth;
  Samples normal;
  Samples axis;
};

struct FamilyAcc {
  FamilyValidation out;
  Samples closed_distance;
  Samples closed_normal;
  Samples fcl_distance;
  CollideAcc mpr;
  CollideAcc epa;
};

// A capsule as FCL sees it: Capsule along local z, or Sphere when the axis has zero length (FCL's
// capsule code does handle lz = 0, but a sphere is what a user of FCL would pass).
struct FclShape {
  explicit FclShape(const Capsule& c)
      : capsule(c.radius, detail::capsule_length(c)),
        sphere(c.radius),
        pose(detail::capsule_pose(c)),
        is_sphere(c.p0 == c.p1) {}
  const fcl::CollisionGeometryd* geometry() const {
    return is_sphere ? static_cast<const fcl::CollisionGeometryd*>(&sphere) : &capsule;
  }
  fcl::Capsuled capsule;
  fcl::Sphered sphere;
  fcl::Transform3d pose;
  bool is_sphere;
};

// The exact separating direction to compare normals against. Where the cores are apart it is the
// reference normal. Where they cross (core distance ~0) the minimum translation is along the
// common perpendicular, with either sign equally good. Parallel touching cores: no unique answer.
struct ExactNormal {
  bool defined = false;
  bool sign_agnostic = false;
  std::array<L, 3> n{};
};

ExactNormal exact_normal(const ReferenceContact& r, const Capsule& a, const Capsule& b) {
  ExactNormal e;
  if (r.core_distance > 1e-9L) {
    e.defined = true;
    e.n = r.normal;
    return e;
  }
  const std::array<L, 3> d1{L(a.p1.x) - L(a.p0.x), L(a.p1.y) - L(a.p0.y), L(a.p1.z) - L(a.p0.z)};
  const std::array<L, 3> d2{L(b.p1.x) - L(b.p0.x), L(b.p1.y) - L(b.p0.y), L(b.p1.z) - L(b.p0.z)};
  const std::array<L, 3> c{d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2],
                           d1[0] * d2[1] - d1[1] * d2[0]};
  const L cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
  const L aa = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2];
  const L bb = d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2];
  if (cc > 1e-12L * aa * bb) {
    const L len = std::sqrt(cc);
    e.defined = true;
    e.sign_agnostic = true;
    e.n = {c[0] / len, c[1] / len, c[2] / len};
  }
  return e;
}

double angle_to(const Vec3& n, const ExactNormal& e, bool ignore_sign = false) {
  auto chord = [&](L sign) {
    const L dx = L(n.x) - sign * e.n[0];
    const L dy = L(n.y) - sign * e.n[1];
    const L dz = L(n.z) - sign * e.n[2];
    return std::sqrt(dx * dx + dy * dy + dz * dz);
  };
  L c = chord(1.0L);
  if (e.sign_agnostic || ignore_sign) c = std::min(c, chord(-1.0L));
  return static_cast<double>(2.0L * std::asin(std::min(L(1), c / 2.0L)));
}

double coordinate_scale(const Capsule& a, const Capsule& b) {
  double m = 1.0;
  for (const Vec3& p : {a.p0, a.p1, b.p0, b.p1}) {
    m = std::max({m, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
  }
  return m;
}

void run_collide(const Capsule& a, const Capsule& b, const FclShape& fa, const FclShape& fb,
                 fcl::GJKSolverType solver, const ReferenceContact& ref, const ExactNormal& en,
                 CollideAcc& acc) {
  fcl::CollisionRequestd request(1, true);
  request.gjk_solver_type = solver;
  fcl::CollisionResultd result;
  fcl::collide(fa.geometry(), fa.pose, fb.geometry(), fb.pose, request, result);

  const double exact = static_cast<double>(ref.distance);
  const bool hit = result.isCollision();
  bool wrong_sign = (exact < -kVerdictMargin && !hit) || (exact > kVerdictMargin && hit);
  bool bad_depth = false;
  bool bad_normal = false;
  if (hit && exact <= kVerdictMargin && result.numContacts() > 0) {
    const fcl::Contactd& c = result.getContact(0);
    ++acc.stats.compared;
    if (c.penetration_depth < 0.0) wrong_sign = true;
    const double depth_error = std::fabs(c.penetration_depth + exact);
    acc.depth.add(depth_error);
    acc.abs_depth.add(std::fabs(std::fabs(c.penetration_depth) + exact));
    bad_depth = !(depth_error <= kFclDepthTolerance);
    // FCL: normal from its o1 to its o2; we passed a first, so it should point a -> b like ours.
    const Vec3 n = detail::from_fcl(c.o1 == fa.geometry() ? c.normal : fcl::Vector3d(-c.normal));
    if (en.defined) {
      const double ne = angle_to(n, en);
      acc.normal.add(ne);
      acc.axis.add(angle_to(n, en, true));
      bad_normal = !(ne <= kFclNormalTolerance);
    }
    // Is FCL's answer at least a separating translation (if not the shortest)?
    const Vec3 shift = n * c.penetration_depth;
    const Capsule moved_b{b.p0 + shift, b.p1 + shift, b.radius};
    if (capsule_capsule_reference(a, moved_b).distance < -kFclDepthTolerance) {
      ++acc.stats.not_separating;
    }
  }
  acc.stats.wrong_sign += wrong_sign ? 1 : 0;
  acc.stats.bad_depth += bad_depth ? 1 : 0;
  acc.stats.bad_normal += bad_normal ? 1 : 0;
  acc.stats.failed_pairs += (wrong_sign || bad_depth || bad_normal) ? 1 : 0;
}

void evaluate(const CapsulePair& p, FamilyAcc& acc) {
  const Capsule& a = p.a;
  const Capsule& b = p.b;
  const ReferenceContact ref = capsule_capsule_reference(a, b);
  const ExactNormal en = exact_normal(ref, a, b);
  const double scale = coordinate_scale(a, b);
  FamilyValidation& out = acc.out;
  ++out.pairs;
  if (ref.distance < 0.0L) ++out.penetrating;

  // Closed form.
  const Contact c = capsule_capsule(a, b);
  const double err = static_cast<double>(std::fabs(static_cast<L>(c.distance) - ref.distance));
  acc.closed_distance.add(err);
  out.closed_max_scaled_error = std::max(out.closed_max_scaled_error, err / scale);
  if (!(err <= kClosedFormRelativeBound * scale)) ++out.closed_bound_violations;
  if (!std::isfinite(c.distance) || !is_finite(c.normal) ||
      !(std::fabs(length(c.normal) - 1.0) <= 1e-12)) {
    ++out.closed_bad_output;
  }
  if (en.defined) acc.closed_normal.add(angle_to(c.normal, en));

  // FCL.
  const FclShape fa(a);
  const FclShape fb(b);
  if (ref.distance > 0.0L) {
    ++out.separated;
    const fcl::DistanceRequestd dreq;  // libccd, unsigned: never signed (see contact_validation.h)
    fcl::DistanceResultd dres;
    const double fd = fcl::distance(fa.geometry(), fa.pose, fb.geometry(), fb.pose, dreq, dres);
    const double fd_err = static_cast<double>(std::fabs(static_cast<L>(fd) - ref.distance));
    acc.fcl_distance.add(fd_err);
    if (!(fd_err <= kFclDistanceTolerance)) ++out.fcl_distance_failures;
  }
  run_collide(a, b, fa, fb, fcl::GST_LIBCCD, ref, en, acc.mpr);
  // Never fcl::distance with GST_INDEP and signed distance: FCL 0.7 then asserts (aborts) when
  // EPA reports no contact for a penetrating pair. collide() is safe.
  run_collide(a, b, fa, fb, fcl::GST_INDEP, ref, en, acc.epa);
}

FclCollideStats finish(const CollideAcc& acc) {
  FclCollideStats s = acc.stats;
  s.depth_error = acc.depth.stats();
  s.abs_depth_error = acc.abs_depth.stats();
  s.normal_error = acc.normal.stats();
  s.axis_error = acc.axis.stats();
  return s;
}

void finish(FamilyAcc& acc) {
  acc.out.closed_distance = acc.closed_distance.stats();
  acc.out.closed_normal = acc.closed_normal.stats();
  acc.out.fcl_distance = acc.fcl_distance.stats();
  acc.out.mpr = finish(acc.mpr);
  acc.out.epa = finish(acc.epa);
}

void add_counts(FclCollideStats& to, const FclCollideStats& from) {
  to.compared += from.compared;
  to.wrong_sign += from.wrong_sign;
  to.bad_depth += from.bad_depth;
  to.bad_normal += from.bad_normal;
  to.failed_pairs += from.failed_pairs;
  to.not_separating += from.not_separating;
}

}  // namespace

ContactValidation run_contact_validation(std::size_t pairs, std::uint64_t seed) {
  constexpr auto kFamilies = static_cast<std::size_t>(PairFamily::kCount);
  std::vector<FamilyAcc> acc(kFamilies);
  for (std::size_t f = 0; f < kFamilies; ++f) {
    acc[f].out.family = static_cast<PairFamily>(f);
    acc[f].out.name = std::string(family_name(acc[f].out.family));
  }
  CapsulePairGenerator gen(seed);
  for (std::size_t i = 0; i < pairs; ++i) {
    const std::size_t f = i % kFamilies;
    evaluate(gen.next(static_cast<PairFamily>(f)), acc[f]);
  }

  ContactValidation v;
  v.pairs = pairs;
  v.seed = seed;
  FamilyAcc all;
  all.out.name = "all";
  for (FamilyAcc& a : acc) {
    all.out.pairs += a.out.pairs;
    all.out.penetrating += a.out.penetrating;
    all.out.closed_max_scaled_error =
        std::max(all.out.closed_max_scaled_error, a.out.closed_max_scaled_error);
    all.out.closed_bound_violations += a.out.closed_bound_violations;
    all.out.closed_bad_output += a.out.closed_bad_output;
    all.out.fcl_distance_failures += a.out.fcl_distance_failures;
    all.out.separated += a.out.separated;
    add_counts(all.mpr.stats, a.mpr.stats);
    add_counts(all.epa.stats, a.epa.stats);
    all.closed_distance.append(a.closed_distance);
    all.closed_normal.append(a.closed_normal);
    all.fcl_distance.append(a.fcl_distance);
    for (auto [to, from] : {std::pair{&all.mpr, &a.mpr}, std::pair{&all.epa, &a.epa}}) {
      to->depth.append(from->depth);
      to->abs_depth.append(from->abs_depth);
      to->normal.append(from->normal);
      to->axis.append(from->axis);
    }
    finish(a);
    v.families.push_back(std::move(a.out));
  }
  finish(all);
  v.all = std::move(all.out);
  return v;
}

}  // namespace throng::geom
