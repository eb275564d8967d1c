#pragma once
// Private state of StaticScenery, shared by the .cpp files that implement its queries.
#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/collision_geometry.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision_object.h>
#include <fcl/narrowphase/collision_request.h>
#include <fcl/narrowphase/collision_result.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "scenery_shapes.h"
#include "throng/geometry/static_scenery.h"

namespace throng::geom {
namespace detail {

struct ShapeRecord {
  ShapeKind kind = ShapeKind::kBox;
  std::uint32_t slot = 0;  // index into Impl::boxes / cylinders / meshes
  Aabb aabb;
  std::shared_ptr<fcl::CollisionGeometryd> geometry;  // the real shape, for FCL's narrowphase
  fcl::Transform3d pose = fcl::Transform3d::Identity();
  // The broadphase holds an axis-aligned box equal to `aabb` rather than the shape itself: FCL
  // bounds a rotated shape by a cube around its bounding sphere, far too loose for long walls.
  std::unique_ptr<fcl::CollisionObjectd> proxy;
};

// Per-thread scratch so const queries can run concurrently without allocating each call.
struct QueryScratch {
  QueryScratch();
  std::shared_ptr<fcl::Boxd> probe_box;
  std::unique_ptr<fcl::CollisionObjectd> probe;  // axis-aligned query box for the broadphase
  std::vector<std::uint32_t> candidates;
  std::vector<double> baseline;
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
};
QueryScratch& query_scratch();

bool is_upright(const Capsule& c);
UprightCore upright_core(const Capsule& c);
Aabb capsule_aabb(const Capsule& c);
void validate_mover(const Capsule& c, const char* where);

// Tilted mover vs box (box != nullptr) or cylinder: exact core distance by bisection,
// FCL MPR once the core reaches the shape.
SignedPenetration tilted_penetration(const ShapeRecord& shape, const BoxShape* box,
                                     const CylinderShape* cylinder, const Capsule& mover,
                                     QueryScratch& scratch);
// Any mover vs a mesh: FCL's BVH picks the overlapped triangles, exact contact per triangle.
SignedPenetration mesh_penetration(const ShapeRecord& shape, const MeshShape& mesh,
                                   const Capsule& mover, QueryScratch& scratch);

// Up to this many shapes, a query tests every shape's AABB in a loop rather than walking FCL's
// tree. Why: a battlefield has a handful of walls and towers, and walking the tree (and refitting
// its probe box) was about a twentieth of a re-simulated battle tick. The loop makes FCL's overlap
// test on the same boxes, so the candidates are the same.
inline constexpr std::size_t kLinearGatherShapes = 32;

}  // namespace detail

struct StaticScenery::Impl {
  std::vector<detail::ShapeRecord> shapes;
  std::vector<detail::BoxShape> boxes;
  std::vector<detail::CylinderShape> cylinders;
  std::vector<detail::MeshShape> meshes;
  Aabb bounds;
  std::unique_ptr<fcl::DynamicAABBTreeCollisionManagerd> manager;
  // The proxies' AABBs as FCL holds them (its tree's leaves), by shape index: up to
  // detail::kLinearGatherShapes shapes, gather tests them in a loop instead of walking the tree.
  std::vector<Aabb> proxy_aabbs;
  bool built = false;

  std::uint32_t add(ShapeKind kind, std::uint32_t slot, const Aabb& box,
                    std::shared_ptr<fcl::CollisionGeometryd> geometry,
                    const fcl::Transform3d& pose);
  void require_built(const char* where) const;
  // Indices (ascending) of the shapes whose AABB overlaps `box` (touching counts).
  void gather(const Aabb& box, detail::QueryScratch& scratch) const;
  // Signed penetration of the mover into one shape: exact closed forms for upright movers against
  // boxes and cylinders and for meshes; for tilted movers against boxes and cylinders an exact
  // numeric core distance, or FCL MPR once the core is inside.
  detail::SignedPenetration penetration(std::uint32_t shape, const Capsule& mover, bool upright,
                                        detail::QueryScratch& scratch) const;
};

}  // namespace throng::geom
