#pragma once
// Fixed scenery (buildings, walls, ledges, props, terrain meshes) and the queries characters make
// against it. FCL does the broadphase and the general narrowphase, but stays out of this header
// (pimpl) so the engine's users never compile against it.
//
// Usage: add_* shapes, build(), then query from any number of threads (queries are const and use
// thread-local scratch). Adding a shape after build() requires another build() before querying.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "throng/core/vec3.h"
#include "throng/geometry/capsule.h"

namespace throng::geom {

enum class ShapeKind : std::uint8_t { kBox, kCylinder, kMesh };

struct Aabb {
  Vec3 lo;
  Vec3 hi;
};

// One fixed shape the mover penetrates.
//   depth:  penetration depth (> 0), the distance the mover must travel along normal to get out.
//   normal: unit direction to move the mover OUT of the shape.
struct SceneryContact {
  std::uint32_t shape = 0;
  double depth = 0.0;
  Vec3 normal{0.0, 0.0, 1.0};
};

class StaticScenery {
 public:
  // Step tolerance of ground_height: surfaces up to this far above the feet still count as ground.
  static constexpr double kStepTolerance = 0.3;

  StaticScenery();
  ~StaticScenery();
  // A moved-from StaticScenery may only be destroyed or assigned to.
  StaticScenery(StaticScenery&&) noexcept;
  StaticScenery& operator=(StaticScenery&&) noexcept;
  StaticScenery(const StaticScenery&) = delete;
  StaticScenery& operator=(const StaticScenery&) = delete;

  // Each returns the new shape's index (0, 1, 2, ... in insertion order) and throws
  // std::invalid_argument on non-finite or degenerate input.
  // Upright box rotated by yaw_rad about +z; half_extents all > 0.
  std::uint32_t add_box(Vec3 centre, Vec3 half_extents, double yaw_rad);
  // Upright cylinder (axis along z); radius > 0, half_height > 0.
  std::uint32_t add_cylinder(Vec3 centre, double radius, double half_height);
  // Triangle mesh, treated as a two-sided surface (a mover wholly inside a closed mesh touches no
  // triangle and is not reported). Indices must be valid; no zero-area triangles. Winding does
  // not matter.
  std::uint32_t add_mesh(std::vector<Vec3> vertices,
                         std::vector<std::array<std::uint32_t, 3>> triangles);

  // Builds the broadphase. Must be called after the last add_* and before any query.
  void build();
  bool built() const;

  std::size_t size() const;
  ShapeKind shape_kind(std::uint32_t shape) const;
  Aabb aabb(std::uint32_t shape) const;  // tight world AABB of the shape
  Aabb bounds() const;                   // union of all shape AABBs ({0,0} when empty)

  // Appends every shape the mover penetrates (depth > 0), in increasing shape index.
  // Exact (to rounding) in every case where the mover's core segment stays outside the shape:
  //  * upright movers (p0.x == p1.x and p0.y == p1.y) vs boxes and cylinders: closed form, also
  //    when the core is inside (nearest face, up / sideways / down);
  //  * any mover vs meshes: FCL's BVH picks the overlapped triangles, contact per triangle in
  //    closed form, the deepest reported; a core through a triangle leaves by the nearer side of
  //    its plane (meshes are two-sided surfaces);
  //  * tilted movers vs boxes and cylinders: exact core distance by bisection; only once the
  //    core itself is inside does FCL (libccd MPR) answer, with a valid but not necessarily
  //    shortest way out.
  void query(const Capsule& mover, std::vector<SceneryContact>& out) const;
  void query(const UprightCapsule& mover, std::vector<SceneryContact>& out) const;

  // Cheap pre-test: does any shape's AABB overlap the box [lo, hi] (touching counts)?
  bool any_aabb_near(const Vec3& lo, const Vec3& hi) const;

  // Highest top surface at (x, y) that is at or below z_feet + kStepTolerance: box tops, cylinder
  // tops, and any mesh triangle crossing the vertical line through (x, y). The ground plane z = 0
  // is such a surface too; if nothing qualifies (feet below -kStepTolerance) the result is 0.0.
  double ground_height(double x, double y, double z_feet) const;

  // Fraction in [0, 1] of `displacement` the mover can travel before it touches a shape (1 when
  // nothing is hit). Shapes the mover already penetrates at the start only stop it if it would go
  // deeper into them. Sampled at most every radius / 2 and refined by bisection to ~1e-9 of the
  // displacement, so a radius-0.35 mover cannot skip a 0.05 m wall. The returned position is
  // never in (deeper) contact.
  double first_hit_fraction(const Capsule& mover, Vec3 displacement) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace throng::geom
