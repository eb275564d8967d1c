// StaticScenery penetration queries against boxes, rotated boxes, cylinders and meshes, agreement
// of the closed forms with FCL, input validation and the AABB accessors. Expected values are
// derived from the geometry in each test.
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#include <gtest/gtest.h>

#include "geometry/geom_test_util.h"

#include <cmath>
#include <iostream>
#include <random>
#include <stdexcept>
#include <string>

#include "geometry/scenery_impl.h"
#include "throng/geometry/static_scenery.h"

namespace throng::geom {
namespace {

Capsule upright(double x, double y, double z_lo, double z_hi, double r) {
  return {{x, y, z_lo}, {x, y, z_hi}, r};
}

std::vector<SceneryContact> query(const StaticScenery& s, const Capsule& c) {
  std::vector<SceneryContact> out;
  s.query(c, out);
  return out;
}

// Axis-aligned box [lo, hi] as 12 triangles.
void add_box_mesh(StaticScenery& s, const Vec3& lo, const Vec3& hi) {
  std::vector<Vec3> v{{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z},
                      {lo.x, hi.y, lo.z}, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z},
                      {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  std::vector<std::array<std::uint32_t, 3>> t{{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7},
                                              {0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5},
                                              {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  s.add_mesh(std::move(v), std::move(t));
}

constexpr double kR = 0.35;

TEST(GeomScenery, UprightCapsuleAgainstBoxFaceEdgeTopAndInside) {
  StaticScenery s;
  const Vec3 c{0, 0, 1};
  const Vec3 h{1, 0.5, 1};  // x in [-1, 1], y in [-0.5, 0.5], z in [0, 2]
  s.add_box(c, h, 0.0);
  s.build();

  // Side: core 0.2 outside the +x face.
  auto out = query(s, upright(1.2, 0, 0.5, 1.5, kR));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].shape, 0u);
  EXPECT_NEAR(out[0].depth, kR - 0.2, 1e-15);
  expect_vec(out[0].normal, {1, 0, 0}, 1e-15);

  // Vertical edge: core 0.1 outside both +x and +y faces -> distance 0.1 * sqrt(2).
  out = query(s, upright(1.1, 0.6, 0.5, 1.5, kR));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, kR - 0.1 * std::sqrt(2.0), 1e-15);
  expect_vec(out[0].normal, Vec3{1, 1, 0} * (1 / std::sqrt(2.0)), 1e-15);

  // Standing on top, sunk 0.05: core bottom 0.3 above the top face.
  out = query(s, upright(0.2, 0.1, 2.3, 3.3, kR));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, 0.05, 1e-15);
  expect_vec(out[0].normal, {0, 0, 1}, 0.0);

  // Top edge: 0.1 outside +x, 0.2 above the top -> distance sqrt(0.05).
  out = query(s, upright(1.1, 0, 2.2, 3.0, kR));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, kR - std::sqrt(0.05), 1e-15);
  expect_vec(out[0].normal, Vec3{0.1, 0, 0.2} * (1 / std::sqrt(0.05)), 1e-15);

  // Core inside, 0.1 from the -y face: out through -y (0.1 + r), not up (1.5 + r) or +y.
  out = query(s, upright(0.3, -0.4, 0.5, 1.5, kR));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, 0.1 + kR, 1e-15);
  expect_vec(out[0].normal, {0, -1, 0}, 0.0);

  // Clear of the box: nothing.
  EXPECT_TRUE(query(s, upright(1.4, 0, 0.5, 1.5, kR)).empty());
}

TEST(GeomScenery, CoreInsideThinLedgeStepsUp) {
  StaticScenery s;
  s.add_box({0, 0, 0.5}, {2, 2, 0.1}, 0.0);  // ledge z in [0.4, 0.6]
  s.build();
  // Core z in [0.5, 1.5] deep inside the footprint: up costs 0.1 + r, sideways 1.5 + r.
  const auto out = query(s, upright(0.5, 0.5, 0.5, 1.5, kR));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, 0.1 + kR, 1e-15);
  expect_vec(out[0].normal, {0, 0, 1}, 0.0);
}

TEST(GeomScenery, RotatedBox) {
  StaticScenery s;
  const double yaw = 0.6;
  const Vec3 u{std::cos(yaw), std::sin(yaw), 0};
  const Vec3 v{-std::sin(yaw), std::cos(yaw), 0};
  const Vec3 c{3, -2, 1.5};
  const Vec3 h{2.0, 0.25, 1.5};  // a wall 4 m long, 0.5 m thick
  s.add_box(c, h, yaw);
  s.build();

  // 0.1 outside the +v face, 0.7 along the wall.
  const Vec3 p = c + u * 0.7 + v * (h.y + 0.1);
  auto out = query(s, upright(p.x, p.y, 1.0, 2.0, kR));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, kR - 0.1, 1e-14);
  expect_vec(out[0].normal, v, 1e-14);

  // Beyond the -u end and the -v face by 0.1 each: diagonal edge contact.
  const Vec3 q = c - u * (h.x + 0.1) - v * (h.y + 0.1);
  out = query(s, upright(q.x, q.y, 1.0, 2.0, kR));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, kR - 0.1 * std::sqrt(2.0), 1e-14);
  expect_vec(out[0].normal, (u + v) * (-1 / std::sqrt(2.0)), 1e-14);

  // AABB of the rotated footprint.
  const Aabb box = s.aabb(0);
  const double ex = std::cos(yaw) * h.x + std::sin(yaw) * h.y;
  const double ey = std::sin(yaw) * h.x + std::cos(yaw) * h.y;
  expect_vec(box.lo, c - Vec3{ex, ey, h.z}, 1e-14);
  expect_vec(box.hi, c + Vec3{ex, ey, h.z}, 1e-14);
}

TEST(GeomScenery, Cylinder) {
  StaticScenery s;
  s.add_cylinder({1, 1, 1}, 0.5, 1.0);  // z in [0, 2]
  s.build();
  // Diagonal approach: axis distance 0.7 -> core 0.2 outside the surface.
  const double d = 0.7 / std::sqrt(2.0);
  auto out = query(s, upright(1 + d, 1 + d, 0.5, 1.5, kR));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, kR - 0.2, 1e-15);
  expect_vec(out[0].normal, Vec3{1, 1, 0} * (1 / std::sqrt(2.0)), 1e-15);
  // Core inside, 0.1 from the surface: radial way out.
  out = query(s, upright(1, 1.4, 0.5, 1.5, kR));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, 0.1 + kR, 1e-15);
  expect_vec(out[0].normal, {0, 1, 0}, 1e-15);
  // Below the bottom rim: core top 0.1 below z = 0 and 0.1 outside the radius.
  out = query(s, upright(1.6, 1, -1.0, -0.1, kR));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, kR - std::sqrt(0.1 * 0.1 + 0.1 * 0.1), 1e-15);
  expect_vec(out[0].normal, Vec3{1, 0, -1} * (1 / std::sqrt(2.0)), 1e-15);

  // Tilted 0.4 rad about y towards the cylinder: the upper core end leads, 0.15 from the side.
  const double a = 0.4;
  const Vec3 half{-0.5 * std::sin(a), 0, 0.5 * std::cos(a)};
  const Vec3 centre = Vec3{1 + 0.5 + 0.15 - half.x, 1, 1.0};
  out = query(s, {centre - half, centre + half, kR});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, kR - 0.15, 1e-15);
  expect_vec(out[0].normal, {1, 0, 0}, 1e-15);
  // ... and over the top rim: the upper end 0.1 beyond the radius and 0.1 above the top, tilted
  // past 45 degrees so that the core recedes from the rim (the end is the closest core point).
  const double b = 0.9;
  const Vec3 half_b{-0.5 * std::sin(b), 0, 0.5 * std::cos(b)};
  const Vec3 rim = Vec3{1 + 0.5 + 0.1 - half_b.x, 1, 2.0 + 0.1 - half_b.z};
  out = query(s, {rim - half_b, rim + half_b, kR});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, kR - 0.1 * std::sqrt(2.0), 1e-15);
  expect_vec(out[0].normal, Vec3{1, 0, 1} * (1 / std::sqrt(2.0)), 1e-15);
}

TEST(GeomScenery, BoxMeshMatchesGeometry) {
  StaticScenery s;
  add_box_mesh(s, {0, -0.5, 0}, {1, 0.5, 2});
  s.build();
  // Upright capsule 0.3 left of the x = 0 face: depth 0.05, pushed to -x.
  auto out = query(s, upright(-0.3, 0, 0.35, 1.35, kR));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, 0.05, 1e-15);
  expect_vec(out[0].normal, {-1, 0, 0}, 1e-15);

  // Tilted 0.3 rad about y towards the face: the upper core end is 0.3 - 0.5 sin(0.3) away.
  const double a = 0.3;
  const Vec3 centre{-0.3, 0.1, 0.85};
  const Vec3 half{0.5 * std::sin(a), 0, 0.5 * std::cos(a)};
  out = query(s, {centre - half, centre + half, kR});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, kR - (0.3 - 0.5 * std::sin(a)), 1e-15);
  expect_vec(out[0].normal, {-1, 0, 0}, 1e-15);

  // A sphere-like mover (zero-length core) on the top face, sunk 0.1.
  out = query(s, {{0.5, 0, 2.25}, {0.5, 0, 2.25}, kR});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, 0.1, 1e-15);
  expect_vec(out[0].normal, {0, 0, 1}, 1e-15);

  // Core through the x = 0 face, its upper end 0.1 inside: out the near side, 0.1 + r along -x
  // (a two-sided surface is left by the nearer side of the pierced triangle's plane).
  const Vec3 deep{0.1 - half.x, 0.05, 0.9};
  out = query(s, {deep - half, deep + half, kR});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, 0.1 + kR, 1e-15);
  expect_vec(out[0].normal, {-1, 0, 0}, 1e-15);
}

TEST(GeomScenery, TiltedCapsuleAgainstBoxAndMeshAgree) {
  // Same geometry as a primitive box and as a mesh: both FCL paths must give the same answer.
  StaticScenery s;
  s.add_box({0.5, 0, 1}, {0.5, 0.5, 1}, 0.0);
  add_box_mesh(s, {10, -0.5, 0}, {11, 0.5, 2});  // the same box, 10 m further along x
  s.build();
  const double a = 0.3;
  const Vec3 centre{-0.3, 0.1, 0.85};
  const Vec3 half{0.5 * std::sin(a), 0, 0.5 * std::cos(a)};
  const auto box = query(s, {centre - half, centre + half, kR});
  const Vec3 shift{10, 0, 0};
  const auto mesh = query(s, {centre - half + shift, centre + half + shift, kR});
  ASSERT_EQ(box.size(), 1u);
  ASSERT_EQ(mesh.size(), 1u);
  EXPECT_EQ(box[0].shape, 0u);
  EXPECT_EQ(mesh[0].shape, 1u);
  const double expected = kR - (0.3 - 0.5 * std::sin(a));
  EXPECT_NEAR(box[0].depth, expected, 1e-14);
  EXPECT_NEAR(mesh[0].depth, expected, 1e-15);
  expect_vec(box[0].normal, {-1, 0, 0}, 1e-14);
  expect_vec(mesh[0].normal, {-1, 0, 0}, 1e-15);
}

TEST(GeomScenery, MeshBoxMatchesPrimitiveBoxOnRandomPoses) {
  // The same box as a primitive (closed form for upright movers, FCL GJK for tilted ones) and as
  // a 12-triangle mesh (exact segment-triangle contacts): wherever the core is outside the box
  // both must give the same contact.
  StaticScenery prim;
  prim.add_box({0.5, 0, 1}, {0.5, 0.5, 1}, 0.0);
  prim.build();
  StaticScenery mesh;
  add_box_mesh(mesh, {0, -0.5, 0}, {1, 0.5, 2});
  mesh.build();
  std::uint64_t state = 777;
  auto next = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  int upright_compared = 0;
  int tilted_compared = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 c{-0.5 + 2.0 * next(), -1.0 + 2.0 * next(), -0.5 + 3.0 * next()};
    const bool tilted = i % 2 == 1;
    const Vec3 axis = tilted ? Vec3{next() - 0.5, next() - 0.5, 0.5 + next()} * 0.6
                             : Vec3{0, 0, 0.2 + 0.6 * next()};
    const Capsule m{c - axis, c + axis, 0.1 + 0.3 * next()};
    const auto a = query(prim, m);
    const auto b = query(mesh, m);
    // Compare only where the primitive says the core is clear of the box (depth < radius).
    if (a.empty() || !(a[0].depth < m.radius - 1e-9)) continue;
    ASSERT_EQ(b.size(), 1u) << i;
    const double tol = tilted ? 1e-13 : 1e-14;
    ASSERT_NEAR(a[0].depth, b[0].depth, tol) << i;
    if (a[0].depth < m.radius - 1e-6) {  // normals are well defined away from touching cores
      ASSERT_NEAR(length(a[0].normal - b[0].normal), 0.0, 1e-12) << i;
    }
    ++(tilted ? tilted_compared : upright_compared);
  }
  EXPECT_GT(upright_compared, 200);
  EXPECT_GT(tilted_compared, 200);
}

TEST(GeomScenery, DeepTiltedContactGivesValidPushOut) {
  // Tilted movers whose core reaches inside a box / a box mesh: the FCL fallback (MPR) must
  // report a push-out that really separates, and no shorter than the true minimum (0.1 + r out
  // through the x = 0 face for a core end 0.1 inside it).
  StaticScenery s;
  s.add_box({0.5, 0, 1}, {0.5, 0.5, 1}, 0.0);  // x in [0, 1]
  add_box_mesh(s, {10, -0.5, 0}, {11, 0.5, 2});
  s.build();
  const double a = 0.3;
  const Vec3 half{0.5 * std::sin(a), 0, 0.5 * std::cos(a)};
  for (const double x0 : {0.0, 10.0}) {
    const Vec3 centre{x0 + 0.1 - half.x, 0.05, 0.9};  // upper core end 0.1 inside the face
    const Capsule m{centre - half, centre + half, kR};
    const auto out = query(s, m);
    ASSERT_EQ(out.size(), 1u) << x0;
    EXPECT_GE(out[0].depth, 0.1 + kR - 1e-6) << x0;
    EXPECT_NEAR(length(out[0].normal), 1.0, 1e-12);
    const Vec3 push = out[0].normal * (out[0].depth + 1e-6);
    const auto after = query(s, {m.p0 + push, m.p1 + push, kR});
    EXPECT_TRUE(after.empty() || after[0].depth < 1e-6)
        << x0 << " depth " << out[0].depth << " n " << out[0].normal.x << " " << out[0].normal.y
        << " " << out[0].normal.z << " after " << after[0].depth << " " << after[0].normal.x << " "
        << after[0].normal.y << " " << after[0].normal.z;
  }
}

// The closed forms against FCL on the same shapes: FCL's GJK distance from the core segment (a
// zero-radius FCL capsule) gives depth = r - d and the witness direction. FCL's own GJK at a tight
// tolerance: libccd's GJK (FCL's default) is up to 6 mm off at a cylinder's rim.
struct FclDepth {
  double depth;
  Vec3 normal;
};
FclDepth fcl_core_depth(const fcl::CollisionGeometryd& shape, const fcl::Transform3d& pose,
                        const Capsule& c) {
  const double len = length(c.p1 - c.p0);
  fcl::Capsuled core(0.0, len);  // upright: local z is world z
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.translation() = fcl::Vector3d(c.p0.x, c.p0.y, 0.5 * (c.p0.z + c.p1.z));
  fcl::DistanceRequestd req(true, false, 0.0, 0.0, 1e-13, fcl::GST_INDEP);
  fcl::DistanceResultd res;
  const double d = fcl::distance(&core, tf, &shape, pose, req, res);
  const fcl::Vector3d n = (res.nearest_points[0] - res.nearest_points[1]).normalized();
  return {c.radius - d, {n.x(), n.y(), n.z()}};
}

TEST(GeomScenery, ClosedFormsAgreeWithFcl) {
  StaticScenery s;
  const Vec3 bc{0, 0, 1};
  const Vec3 bh{1, 0.5, 1};
  const double yaw = 0.4;
  s.add_box(bc, bh, yaw);
  const Vec3 cc{5, 0, 1};
  s.add_cylinder(cc, 0.6, 1.0);
  s.build();

  fcl::Boxd box(2 * bh.x, 2 * bh.y, 2 * bh.z);
  fcl::Transform3d box_pose = fcl::Transform3d::Identity();
  box_pose.translation() = fcl::Vector3d(bc.x, bc.y, bc.z);
  box_pose.linear() = Eigen::AngleAxisd(yaw, fcl::Vector3d::UnitZ()).toRotationMatrix();
  fcl::Cylinderd cyl(0.6, 2.0);
  fcl::Transform3d cyl_pose = fcl::Transform3d::Identity();
  cyl_pose.translation() = fcl::Vector3d(cc.x, cc.y, cc.z);

  // Movers around both shapes with the core outside (the regime where FCL's distance is exact):
  // sides, vertical edges, top edges and tops.
  int compared = 0;
  double worst_depth = 0.0;
  double worst_normal = 0.0;
  for (int k = 0; k < 48; ++k) {
    const double phi = 0.1309 * k;
    for (const double z_lo : {0.5, 2.2}) {
      for (const bool cylinder : {false, true}) {
        const Vec3 centre = cylinder ? cc : bc;
        const double reach = cylinder ? 0.6 + 0.15 : (k % 2 ? 0.7 : 1.1);
        const double sink = z_lo > 2.0 ? 0.2 * (k % 3) : 0.0;
        const Capsule m =
            upright(centre.x + reach * std::cos(phi), centre.y + reach * std::sin(phi), z_lo - sink,
                    z_lo - sink + 1.0, kR);
        std::vector<SceneryContact> out;
        s.query(m, out);
        const FclDepth f =
            cylinder ? fcl_core_depth(cyl, cyl_pose, m) : fcl_core_depth(box, box_pose, m);
        if (!(f.depth > 1e-6 && f.depth < kR - 1e-6)) continue;  // core outside and touching
        ASSERT_EQ(out.size(), 1u) << k;
        EXPECT_NEAR(out[0].depth, f.depth, 1e-8) << "k=" << k << " cyl=" << cylinder;
        expect_vec(out[0].normal, f.normal, 1e-6);
        worst_depth = std::max(worst_depth, std::fabs(out[0].depth - f.depth));
        worst_normal = std::max(worst_normal, length(out[0].normal - f.normal));
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 60);
  std::cout << "closed form vs FCL GJK over " << compared << " poses: max |depth diff| "
            << worst_depth << " m, max |normal diff| " << worst_normal << "\n";

  // Where MPR's push-out direction is the shortest one (mover straight out from a face),
  // fcl::collide agrees as well.
  const Vec3 face_n{std::cos(yaw), std::sin(yaw), 0};
  const Vec3 p = bc + face_n * (bh.x + 0.2);
  const Capsule m = upright(p.x, p.y, 0.5, 1.5, kR);
  fcl::Capsuled cap(kR, 1.0);
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.translation() = fcl::Vector3d(p.x, p.y, 1.0);
  fcl::CollisionRequestd req(1, true);
  fcl::CollisionResultd res;
  fcl::collide(&cap, tf, &box, box_pose, req, res);
  ASSERT_TRUE(res.isCollision());
  std::vector<SceneryContact> out;
  s.query(m, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, res.getContact(0).penetration_depth, 1e-6);
  const fcl::Vector3d n = -res.getContact(0).normal;  // FCL: capsule -> box
  expect_vec(out[0].normal, {n.x(), n.y(), n.z()}, 1e-6);
}

TEST(GeomScenery, ResultsOrderedByShapeIndex) {
  StaticScenery s;
  s.add_box({1.2, 0, 1}, {0.1, 1, 1}, 0.0);   // 0: right wall
  s.add_cylinder({0, 1.1, 1}, 0.2, 1.0);      // 1: post behind
  s.add_box({-1.2, 0, 1}, {0.1, 1, 1}, 0.0);  // 2: left wall
  s.add_box({30, 0, 1}, {1, 1, 1}, 0.0);      // 3: far away
  s.build();
  const auto out = query(s, upright(0, 0, 0.5, 1.5, 1.2));
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].shape, 0u);
  EXPECT_EQ(out[1].shape, 1u);
  EXPECT_EQ(out[2].shape, 2u);
  expect_vec(out[0].normal, {-1, 0, 0}, 0.0);
  expect_vec(out[1].normal, {0, -1, 0}, 0.0);
  expect_vec(out[2].normal, {1, 0, 0}, 0.0);
  // Appends: the caller's vector is not cleared.
  std::vector<SceneryContact> again = out;
  s.query(UprightCapsule{0, 0, 1.0, 0.5, 1.2}, again);
  EXPECT_EQ(again.size(), 6u);
}

// A small scenery's queries test the shapes' boxes in a loop (detail::kLinearGatherShapes); a large
// one walks FCL's tree. The same shapes queried both ways (the second scenery has far-away shapes
// added after them) give the same contacts, bit for bit: upright and tilted movers, touching,
// grazing and deep, against boxes (rotated too), cylinders and a mesh.
TEST(GeomScenery, SmallSceneryLoopFindsWhatTheTreeFinds) {
  static_assert(detail::kLinearGatherShapes >= 20 && detail::kLinearGatherShapes < 45);
  StaticScenery small, large;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(-8.0, 8.0), ext(0.1, 2.0), yaw(-3.2, 3.2);
  auto add = [&](StaticScenery& s, int k, double dx) {
    if (k % 4 == 3) {
      const double x = 3.0 * (k % 3) - 3.0 + dx, y = 2.0 * (k % 5) - 4.0;
      add_box_mesh(s, {x, y, 0.0}, {x + 0.8, y + 0.6, 2.0});
    } else if (k % 4 == 2) {
      s.add_cylinder({pos(rng) + dx, pos(rng), 1.0}, ext(rng), 1.0);
    } else {
      s.add_box({pos(rng) + dx, pos(rng), ext(rng)}, {ext(rng), ext(rng), ext(rng)}, k % 2 == 0 ? 0.0 : yaw(rng));
    }
  };
  const auto seed_state = rng;
  for (int k = 0; k < 20; ++k) add(small, k, 0.0);
  rng = seed_state;
  for (int k = 0; k < 20; ++k) add(large, k, 0.0);
  for (int k = 0; k < 25; ++k) add(large, k, 5000.0);
  small.build();
  large.build();
  ASSERT_LE(small.size(), detail::kLinearGatherShapes);
  ASSERT_GT(large.size(), detail::kLinearGatherShapes);
  std::uniform_real_distribution<double> at(-10.0, 10.0), tilt(-0.6, 0.6), radius(0.2, 1.2);
  std::vector<Capsule> movers;
  for (int q = 0; q < 4000; ++q) {
    const double x = at(rng), y = at(rng), r = radius(rng);
    movers.push_back(q % 3 == 0 ? Capsule{{x, y, 0.2}, {x + tilt(rng), y + tilt(rng), 1.6}, r} : upright(x, y, 0.2, 1.6, r));
  }
  // Movers whose box grazes a shape's box: a few ulps either side of touching on x and on y, where
  // a probe box computed other than FCL's would let one more or one fewer candidate through.
  for (std::uint32_t i = 0; i < small.size(); ++i) {
    const Aabb box = small.aabb(i);
    const double r = 0.35;
    double x = box.hi.x + r, y = box.hi.y + r;
    for (int k = 0; k < 30; ++k) x = std::nextafter(x, -1e300), y = std::nextafter(y, -1e300);
    for (int k = 0; k < 60; ++k) {
      movers.push_back(upright(x, 0.5 * (box.lo.y + box.hi.y), 0.2, 1.6, r));
      movers.push_back(upright(0.5 * (box.lo.x + box.hi.x), y, 0.2, 1.6, r));
      x = std::nextafter(x, 1e300);
      y = std::nextafter(y, 1e300);
    }
  }
  std::size_t contacts = 0, candidates = 0;
  for (std::size_t q = 0; q < movers.size(); ++q) {
    const Capsule& mover = movers[q];
    const auto a = query(small, mover);
    const std::vector<std::uint32_t> loop_candidates = detail::query_scratch().candidates;
    const auto b = query(large, mover);
    // The candidates themselves, not only the contacts (a contact needs depth > 0, so an extra
    // candidate would not show there).
    ASSERT_EQ(loop_candidates, detail::query_scratch().candidates) << "query " << q;
    candidates += loop_candidates.size();
    ASSERT_EQ(a.size(), b.size()) << "query " << q;
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].shape, b[i].shape);
      EXPECT_EQ(a[i].depth, b[i].depth);
      EXPECT_EQ(a[i].normal.x, b[i].normal.x);
      EXPECT_EQ(a[i].normal.y, b[i].normal.y);
      EXPECT_EQ(a[i].normal.z, b[i].normal.z);
    }
    contacts += a.size();
  }
  EXPECT_GT(contacts, 1000u);  // the movers meet the shapes often, not only the empty floor
  EXPECT_GT(candidates, contacts);  // and graze some they do not touch
}

TEST(GeomScenery, AccessorsAndNearTest) {
  StaticScenery s;
  EXPECT_EQ(s.add_box({0, 0, 1}, {1, 1, 1}, 0.0), 0u);
  EXPECT_EQ(s.add_cylinder({5, 0, 1}, 0.5, 1.0), 1u);
  std::vector<Vec3> v{{10, 0, 0}, {11, 0, 0}, {10, 1, 0.5}};
  EXPECT_EQ(s.add_mesh(v, {{0, 1, 2}}), 2u);
  EXPECT_FALSE(s.built());
  EXPECT_THROW(s.any_aabb_near({0, 0, 0}, {1, 1, 1}), std::logic_error);
  s.build();
  EXPECT_TRUE(s.built());
  EXPECT_EQ(s.size(), 3u);
  EXPECT_EQ(s.shape_kind(0), ShapeKind::kBox);
  EXPECT_EQ(s.shape_kind(1), ShapeKind::kCylinder);
  EXPECT_EQ(s.shape_kind(2), ShapeKind::kMesh);
  EXPECT_THROW(s.shape_kind(3), std::out_of_range);
  expect_vec(s.aabb(1).lo, {4.5, -0.5, 0}, 0.0);
  expect_vec(s.aabb(2).hi, {11, 1, 0.5}, 0.0);
  expect_vec(s.bounds().lo, {-1, -1, 0}, 0.0);
  expect_vec(s.bounds().hi, {11, 1, 2}, 0.0);

  EXPECT_TRUE(s.any_aabb_near({1, 1, 2}, {3, 3, 3}));          // touches the box's corner
  EXPECT_TRUE(s.any_aabb_near({5.4, 0.4, 1}, {5.6, 0.6, 1}));  // inside the cylinder's AABB
  EXPECT_FALSE(s.any_aabb_near({2, -3, 0}, {4, -2, 5}));
  EXPECT_FALSE(s.any_aabb_near({1.01, 0, 0}, {4.49, 1, 2}));  // between box and cylinder
}

TEST(GeomScenery, BadInputsThrow) {
  StaticScenery s;
  const double nan = std::nan("");
  EXPECT_THROW(s.add_box({nan, 0, 0}, {1, 1, 1}, 0), std::invalid_argument);
  EXPECT_THROW(s.add_box({0, 0, 0}, {1, 0, 1}, 0), std::invalid_argument);
  EXPECT_THROW(s.add_box({0, 0, 0}, {1, -1, 1}, 0), std::invalid_argument);
  EXPECT_THROW(s.add_box({0, 0, 0}, {1, 1, INFINITY}, 0), std::invalid_argument);
  EXPECT_THROW(s.add_box({0, 0, 0}, {1, 1, 1}, nan), std::invalid_argument);
  EXPECT_THROW(s.add_cylinder({0, 0, 0}, 0.0, 1), std::invalid_argument);
  EXPECT_THROW(s.add_cylinder({0, 0, 0}, 1, -1), std::invalid_argument);
  EXPECT_THROW(s.add_cylinder({0, INFINITY, 0}, 1, 1), std::invalid_argument);

  const std::vector<Vec3> tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_THROW(s.add_mesh({}, {{0, 1, 2}}), std::invalid_argument);
  EXPECT_THROW(s.add_mesh(tri, {}), std::invalid_argument);
  EXPECT_THROW(s.add_mesh({{0, 0, 0}, {1, 0, nan}, {0, 1, 0}}, {{0, 1, 2}}), std::invalid_argument);
  EXPECT_THROW(s.add_mesh(tri, {{0, 1, 2}, {0, 1, 2}, {0, 1, 3}}), std::invalid_argument);
  EXPECT_THROW(s.add_mesh(tri, {{0, 1, 1}}), std::invalid_argument);
  EXPECT_THROW(s.add_mesh({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}, {{0, 1, 2}}),  // collinear
               std::invalid_argument);
  try {
    s.add_mesh(tri, {{0, 1, 2}, {2, 1, 7}});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("add_mesh"), std::string::npos) << what;
    EXPECT_NE(what.find("triangle 1"), std::string::npos) << what;
    EXPECT_NE(what.find("index 7"), std::string::npos) << what;
  }
  EXPECT_EQ(s.size(), 0u);  // nothing half-added

  s.add_box({0, 0, 1}, {1, 1, 1}, 0.0);
  std::vector<SceneryContact> out;
  EXPECT_THROW(s.query(upright(0, 0, 0, 1, 0.3), out), std::logic_error);  // not built
  s.build();
  EXPECT_THROW(s.query(upright(0, 0, 0, 1, 0.0), out), std::invalid_argument);
  EXPECT_THROW(s.query(upright(nan, 0, 0, 1, 0.3), out), std::invalid_argument);
}

}  // namespace
}  // namespace throng::geom
