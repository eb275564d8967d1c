// capsule_capsule and the upright fast path: hand-built cases, degenerate (touching-core)
// fallbacks, antisymmetry, and equality of the upright path with the general one.
#include <gtest/gtest.h>

#include "geometry/geom_test_util.h"

#include <cmath>
#include <cstring>

#include "throng/geometry/capsule_contact.h"
#include "throng/geometry/capsule_pair_generator.h"
#include "geometry/upright_contact.h"

namespace throng::geom {
namespace {

TEST(GeomCapsuleContact, SeparatedSpheres) {
  const Contact c = capsule_capsule({{0, 0, 0}, {0, 0, 0}, 1.0}, {{3, 0, 0}, {3, 0, 0}, 0.5});
  EXPECT_DOUBLE_EQ(c.distance, 1.5);
  EXPECT_EQ(c.normal, (Vec3{1, 0, 0}));
  EXPECT_EQ(c.point_a, (Vec3{0, 0, 0}));
  EXPECT_EQ(c.point_b, (Vec3{3, 0, 0}));
}

TEST(GeomCapsuleContact, PenetratingSideBySide) {
  // Upright capsules 0.5 apart with radii 0.3 + 0.4: depth 0.2, pushing b along +y.
  const Contact c = capsule_capsule({{0, 0, 0}, {0, 0, 1}, 0.3}, {{0, 0.5, 0.5}, {0, 0.5, 2}, 0.4});
  EXPECT_NEAR(c.distance, -0.2, 1e-15);
  expect_vec(c.normal, {0, 1, 0}, 1e-15);
  EXPECT_NEAR(c.point_a.z, 0.75, 1e-15);  // middle of the z overlap [0.5, 1]
  EXPECT_NEAR(c.point_b.z, 0.75, 1e-15);
}

TEST(GeomCapsuleContact, CrossingCoresUseCommonPerpendicular) {
  const Capsule a{{-1, 0, 0}, {1, 0, 0}, 0.25};
  const Capsule b{{0, -1, 0}, {0, 1, 0}, 0.5};
  const Contact ab = capsule_capsule(a, b);
  EXPECT_DOUBLE_EQ(ab.distance, -0.75);
  EXPECT_EQ(ab.normal, (Vec3{0, 0, 1}));  // x cross y: the exact minimum-translation axis
  const Contact ba = capsule_capsule(b, a);
  EXPECT_EQ(ba.normal, (Vec3{0, 0, -1}));  // antisymmetric under swap
  // Moving b by depth along the normal separates them exactly.
  const Vec3 push = ab.normal * -ab.distance;
  EXPECT_NEAR(capsule_capsule(a, {b.p0 + push, b.p1 + push, b.radius}).distance, 0.0, 1e-15);
}

TEST(GeomCapsuleContact, NearlyTouchingCoresFollowTheOffsetSide) {
  // Cores 1e-17 apart (below the noise threshold): the fallback must agree with the direction
  // the true difference vector has, i.e. towards b's side.
  const Contact c =
      capsule_capsule({{-1, 0, 0}, {1, 0, 0}, 0.25}, {{0, -1, -1e-17}, {0, 1, -1e-17}, 0.25});
  EXPECT_EQ(c.normal, (Vec3{0, 0, -1}));
}

TEST(GeomCapsuleContact, CoaxialAndCoincidentFallbacksAreHorizontal) {
  // Stacked upright capsules with overlapping cores: +x, as the upright path does.
  const Contact up = capsule_capsule({{2, 3, 0}, {2, 3, 1}, 0.3}, {{2, 3, 0.5}, {2, 3, 2}, 0.3});
  EXPECT_EQ(up.normal, (Vec3{1, 0, 0}));
  EXPECT_DOUBLE_EQ(up.distance, -0.6);
  // Coincident sphere centres: +x.
  EXPECT_EQ(capsule_capsule({{1, 1, 1}, {1, 1, 1}, 0.2}, {{1, 1, 1}, {1, 1, 1}, 0.2}).normal,
            (Vec3{1, 0, 0}));
  // Collinear horizontal capsules along x: horizontal and perpendicular to the axis, +y.
  EXPECT_EQ(capsule_capsule({{0, 0, 1}, {2, 0, 1}, 0.2}, {{1, 0, 1}, {3, 0, 1}, 0.2}).normal,
            (Vec3{0, 1, 0}));
  // Collinear along y: +x.
  EXPECT_EQ(capsule_capsule({{0, 0, 1}, {0, 2, 1}, 0.2}, {{0, 1, 1}, {0, 3, 1}, 0.2}).normal,
            (Vec3{1, 0, 0}));
  // A sphere centred on a tilted axis: horizontal, perpendicular to that axis.
  const Contact s =
      capsule_capsule({{0, 0, 0}, {1, 1, 1}, 0.2}, {{0.5, 0.5, 0.5}, {0.5, 0.5, 0.5}, 0.1});
  EXPECT_NEAR(s.normal.z, 0.0, 0.0);
  EXPECT_NEAR(dot(s.normal, Vec3{1, 1, 1}), 0.0, 1e-15);
  EXPECT_NEAR(length(s.normal), 1.0, 1e-15);
}

TEST(GeomCapsuleContact, AntisymmetricAndFiniteOnRandomPairs) {
  CapsulePairGenerator gen(42);
  for (int i = 0; i < 20'000; ++i) {
    const CapsulePair p =
        gen.next(static_cast<PairFamily>(i % static_cast<int>(PairFamily::kCount)));
    const Contact ab = capsule_capsule(p.a, p.b);
    const Contact ba = capsule_capsule(p.b, p.a);
    ASSERT_TRUE(std::isfinite(ab.distance));
    ASSERT_TRUE(is_finite(ab.normal));
    ASSERT_NEAR(length(ab.normal), 1.0, 1e-12);
    ASSERT_NEAR(ab.distance, ba.distance, 1e-12) << family_name(p.family);
    // Normals flip under swap wherever the cores are clearly apart.
    if (ab.distance + p.a.radius + p.b.radius > 1e-9) {
      ASSERT_NEAR(dot(ab.normal, ba.normal), -1.0, 1e-9) << family_name(p.family);
    }
  }
}

TEST(GeomCapsuleContact, DeterministicBitForBit) {
  CapsulePairGenerator g1(7);
  CapsulePairGenerator g2(7);
  for (int i = 0; i < 5'000; ++i) {
    const auto f = static_cast<PairFamily>(i % static_cast<int>(PairFamily::kCount));
    const CapsulePair p = g1.next(f);
    const CapsulePair q = g2.next(f);
    const Contact a = capsule_capsule(p.a, p.b);
    const Contact b = capsule_capsule(q.a, q.b);
    ASSERT_EQ(std::memcmp(&a, &b, sizeof(Contact)), 0);
  }
}

// ---- upright fast path ---------------------------------------------------------------------

UprightCapsule random_upright(CapsulePairGenerator& g, const Vec3& around, double spread) {
  UprightCapsule u;
  u.x = around.x + g.uniform(-spread, spread);
  u.y = around.y + g.uniform(-spread, spread);
  u.z = around.z + g.uniform(0.0, 2.0 * spread);
  const double pick = g.uniform01();
  u.half_height = pick < 0.15 ? 0.0 : g.uniform(0.0, 0.9);  // some spheres
  u.radius = g.uniform(0.1, 0.5);
  return u;
}

TEST(GeomUprightContact, EqualsGeneralFunctionOnUprightPairs) {
  CapsulePairGenerator g(2024);
  int coaxial = 0;
  for (int i = 0; i < 50'000; ++i) {
    const Vec3 around = (i % 4 == 3) ? Vec3{1e4, -1e4, 3.0} : Vec3{0, 0, 0};
    const UprightCapsule a = random_upright(g, around, 1.0);
    UprightCapsule b = random_upright(g, around, 1.0);
    if (i % 10 == 0) {  // coaxial: same x, y (stacked or overlapping)
      b.x = a.x;
      b.y = a.y;
    }
    if (i % 10 == 1) b.z = a.z + (a.half_height + b.half_height) * g.uniform(-1.0, 1.0);
    const Contact fast = upright_capsule_capsule(a, b);
    const Contact general = capsule_capsule(to_capsule(a), to_capsule(b));
    const double scale = std::max(1.0, std::fabs(around.x));
    ASSERT_NEAR(fast.distance, general.distance, 1e-15 * scale) << i;
    expect_vec(fast.point_a, general.point_a, 1e-15 * scale);
    expect_vec(fast.point_b, general.point_b, 1e-15 * scale);
    const double core = fast.distance + a.radius + b.radius;
    if (core > 1e-9) {
      expect_vec(fast.normal, general.normal, 1e-12);
    } else if (core == 0.0) {
      ++coaxial;
      ASSERT_EQ(fast.normal, general.normal) << i;  // the same deterministic fallback (+x)
      ASSERT_EQ(fast.normal, (Vec3{1, 0, 0}));
    }
  }
  EXPECT_GT(coaxial, 100);  // the fallback really was exercised
}

TEST(GeomUprightContact, RequiredHorizontalSeparationJustTouches) {
  CapsulePairGenerator g(99);
  for (int i = 0; i < 10'000; ++i) {
    const UprightCapsule a = random_upright(g, {0, 0, 0}, 1.0);
    UprightCapsule b = random_upright(g, {0, 0, 0}, 1.0);
    const double gap = vertical_gap(a, b);
    const double rs = a.radius + b.radius;
    const double need = required_horizontal_separation(a, b);
    if (gap >= rs) {
      ASSERT_EQ(need, 0.0);
      continue;
    }
    const double phi = g.uniform(0.0, 6.283185307179586);
    b.x = a.x + need * std::cos(phi);
    b.y = a.y + need * std::sin(phi);
    ASSERT_NEAR(upright_capsule_capsule(a, b).distance, 0.0, 1e-14) << i;
  }
  EXPECT_DOUBLE_EQ(required_horizontal_separation(0.3, 0.5), 0.4);  // 3-4-5
  EXPECT_DOUBLE_EQ(required_horizontal_separation(-0.3, 0.5), 0.4);
  EXPECT_EQ(required_horizontal_separation(0.5, 0.5), 0.0);
}

TEST(GeomUprightContact, VerticalGapAndStackedNormals) {
  const UprightCapsule a{0, 0, 1.0, 0.5, 0.3};      // core z in [0.5, 1.5]
  const UprightCapsule above{0, 0, 2.5, 0.5, 0.3};  // [2, 3]: gap 0.5
  EXPECT_DOUBLE_EQ(vertical_gap(a, above), 0.5);
  EXPECT_DOUBLE_EQ(vertical_gap(above, a), 0.5);
  const Contact c = upright_capsule_capsule(a, above);
  EXPECT_DOUBLE_EQ(c.distance, 0.5 - 0.6);
  EXPECT_EQ(c.normal, (Vec3{0, 0, 1}));
  EXPECT_EQ(upright_capsule_capsule(above, a).normal, (Vec3{0, 0, -1}));
}

}  // namespace
}  // namespace throng::geom
