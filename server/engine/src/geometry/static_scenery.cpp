// StaticScenery: shape registration and validation, broadphase, accessors and the penetration
// query. Ground and sweep queries live in scenery_ground.cpp and scenery_sweep.cpp.
#include "throng/geometry/static_scenery.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/math/bv/OBBRSS.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "fcl_shapes.h"
#include "scenery_closed_form.h"
#include "scenery_impl.h"

namespace throng::geom {
namespace detail {

QueryScratch::QueryScratch()
    : probe_box(std::make_shared<fcl::Boxd>(1.0, 1.0, 1.0)),
      probe(std::make_unique<fcl::CollisionObjectd>(probe_box)) {
  probe->setUserData(nullptr);  // FCL leaves user_data uninitialised
  candidates.reserve(64);
  baseline.reserve(64);
  request.enable_contact = true;
  request.gjk_solver_type = fcl::GST_LIBCCD;
}

QueryScratch& query_scratch() {
  thread_local QueryScratch scratch;
  return scratch;
}

bool is_upright(const Capsule& c) { return c.p0.x == c.p1.x && c.p0.y == c.p1.y; }

UprightCore upright_core(const Capsule& c) {
  return {c.p0.x, c.p0.y, std::min(c.p0.z, c.p1.z), std::max(c.p0.z, c.p1.z), c.radius};
}

Aabb capsule_aabb(const Capsule& c) {
  const Vec3 r{c.radius, c.radius, c.radius};
  const Vec3 lo{std::min(c.p0.x, c.p1.x), std::min(c.p0.y, c.p1.y), std::min(c.p0.z, c.p1.z)};
  const Vec3 hi{std::max(c.p0.x, c.p1.x), std::max(c.p0.y, c.p1.y), std::max(c.p0.z, c.p1.z)};
  return {lo - r, hi + r};
}

void validate_mover(const Capsule& c, const char* where) {
  if (!is_finite(c.p0) || !is_finite(c.p1) || !std::isfinite(c.radius) || !(c.radius > 0.0)) {
    throw std::invalid_argument(std::string(where) +
                                ": mover capsule must have finite endpoints and radius > 0");
  }
}

}  // namespace detail

namespace {

std::string describe(const Vec3& v) {
  std::ostringstream s;
  s.precision(17);
  s << '(' << v.x << ", " << v.y << ", " << v.z << ')';
  return s.str();
}

[[noreturn]] void fail(const char* where, const std::string& what) {
  throw std::invalid_argument(std::string("StaticScenery::") + where + ": " + what);
}

bool positive_finite(double v) { return std::isfinite(v) && v > 0.0; }

// Grow a query box by a few ulps of its coordinates so rounding in FCL's box arithmetic can never
// drop a shape that exactly touches it.
Aabb inflate(const Aabb& b) {
  const double m = std::max({1.0, std::fabs(b.lo.x), std::fabs(b.lo.y), std::fabs(b.lo.z),
                             std::fabs(b.hi.x), std::fabs(b.hi.y), std::fabs(b.hi.z)});
  const double pad = 8.0 * DBL_EPSILON * m;
  return {b.lo - Vec3{pad, pad, pad}, b.hi + Vec3{pad, pad, pad}};
}

bool collect_callback(fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* data) {
  auto* out = static_cast<std::vector<std::uint32_t>*>(data);
  for (const fcl::CollisionObjectd* o : {o1, o2}) {
    if (void* tag = o->getUserData()) {  // scenery proxies carry index + 1; the probe carries null
      out->push_back(static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(tag) - 1u));
    }
  }
  return false;  // keep going: we want every candidate
}

bool any_callback(fcl::CollisionObjectd*, fcl::CollisionObjectd*, void* data) {
  *static_cast<bool*>(data) = true;
  return true;  // one is enough
}

void set_probe(detail::QueryScratch& s, const Aabb& q) {
  s.probe_box->side = detail::to_fcl(q.hi - q.lo);
  s.probe_box->computeLocalAABB();
  s.probe->setTranslation(detail::to_fcl((q.lo + q.hi) * 0.5));
  s.probe->computeAABB();
}

}  // namespace

// ---- Impl ---------------------------------------------------------------------------------------

std::uint32_t StaticScenery::Impl::add(ShapeKind kind, std::uint32_t slot, const Aabb& box,
                                       std::shared_ptr<fcl::CollisionGeometryd> geometry,
                                       const fcl::Transform3d& pose) {
  if (shapes.size() >= std::numeric_limits<std::uint32_t>::max() - 1u) {
    throw std::length_error("StaticScenery: too many shapes");
  }
  detail::ShapeRecord r;
  r.kind = kind;
  r.slot = slot;
  r.aabb = box;
  r.geometry = std::move(geometry);
  r.pose = pose;
  auto proxy_box = std::make_shared<fcl::Boxd>(detail::to_fcl(box.hi - box.lo));
  fcl::Transform3d proxy_pose = fcl::Transform3d::Identity();
  proxy_pose.translation() = detail::to_fcl((box.lo + box.hi) * 0.5);
  r.proxy = std::make_unique<fcl::CollisionObjectd>(proxy_box, proxy_pose);
  const auto index = static_cast<std::uint32_t>(shapes.size());
  r.proxy->setUserData(reinterpret_cast<void*>(static_cast<std::uintptr_t>(index) + 1u));
  const Aabb proxy_aabb{detail::from_fcl(r.proxy->getAABB().min_), detail::from_fcl(r.proxy->getAABB().max_)};
  if (shapes.empty()) {
    bounds = box;
  } else {
    bounds.lo = {std::min(bounds.lo.x, box.lo.x), std::min(bounds.lo.y, box.lo.y),
                 std::min(bounds.lo.z, box.lo.z)};
    bounds.hi = {std::max(bounds.hi.x, box.hi.x), std::max(bounds.hi.y, box.hi.y),
                 std::max(bounds.hi.z, box.hi.z)};
  }
  shapes.push_back(std::move(r));
  proxy_aabbs.push_back(proxy_aabb);  // after the shape: the loop's indices are always shapes'
  built = false;  // a new shape needs a new broadphase
  return index;
}

void StaticScenery::Impl::require_built(const char* where) const {
  if (!built) {
    throw std::logic_error(std::string("StaticScenery::") + where +
                           ": call build() after adding shapes and before querying");
  }
}

void StaticScenery::Impl::gather(const Aabb& box, detail::QueryScratch& s) const {
  s.candidates.clear();
  if (shapes.empty()) return;
  if (shapes.size() <= detail::kLinearGatherShapes) {
    // The probe's AABB as set_probe has FCL compute it (Box::computeLocalAABB, then the identity
    // pose's translate), and AABB::overlap's test, shape by shape in index order.
    const Aabb q = inflate(box);
    const Vec3 side = q.hi - q.lo;
    const Vec3 half{0.5 * side.x, 0.5 * side.y, 0.5 * side.z};
    const Vec3 centre = (q.lo + q.hi) * 0.5;
    const Vec3 lo{-half.x + centre.x, -half.y + centre.y, -half.z + centre.z};
    const Vec3 hi{half.x + centre.x, half.y + centre.y, half.z + centre.z};
    for (std::size_t i = 0; i < proxy_aabbs.size(); ++i) {  // never longer than shapes (add)
      const Aabb& b = proxy_aabbs[i];
      const bool apart = lo.x > b.hi.x || lo.y > b.hi.y || lo.z > b.hi.z || hi.x < b.lo.x || hi.y < b.lo.y || hi.z < b.lo.z;
      if (!apart) s.candidates.push_back(static_cast<std::uint32_t>(i));
    }
    return;
  }
  set_probe(s, inflate(box));
  manager->collide(s.probe.get(), &s.candidates, &collect_callback);
  // The tree's visiting order is an implementation detail; results must follow shape index.
  std::sort(s.candidates.begin(), s.candidates.end());
}

detail::SignedPenetration StaticScenery::Impl::penetration(std::uint32_t i, const Capsule& mover,
                                                           bool upright,
                                                           detail::QueryScratch& s) const {
  const detail::ShapeRecord& r = shapes[i];
  if (upright && r.kind == ShapeKind::kBox) {
    return detail::upright_capsule_vs_box(detail::upright_core(mover), boxes[r.slot]);
  }
  if (upright && r.kind == ShapeKind::kCylinder) {
    return detail::upright_capsule_vs_cylinder(detail::upright_core(mover), cylinders[r.slot]);
  }
  if (r.kind == ShapeKind::kMesh) return detail::mesh_penetration(r, meshes[r.slot], mover, s);
  if (r.kind == ShapeKind::kBox)
    return detail::tilted_penetration(r, &boxes[r.slot], nullptr, mover, s);
  return detail::tilted_penetration(r, nullptr, &cylinders[r.slot], mover, s);
}

// ---- StaticScenery ------------------------------------------------------------------------------

StaticScenery::StaticScenery() : impl_(std::make_unique<Impl>()) {}
StaticScenery::~StaticScenery() = default;
StaticScenery::StaticScenery(StaticScenery&&) noexcept = default;
StaticScenery& StaticScenery::operator=(StaticScenery&&) noexcept = default;

std::uint32_t StaticScenery::add_box(Vec3 centre, Vec3 half_extents, double yaw_rad) {
  if (!is_finite(centre)) fail("add_box", "centre must be finite, got " + describe(centre));
  if (!positive_finite(half_extents.x) || !positive_finite(half_extents.y) ||
      !positive_finite(half_extents.z)) {
    fail("add_box", "half_extents must be finite and > 0, got " + describe(half_extents));
  }
  if (!std::isfinite(yaw_rad)) fail("add_box", "yaw_rad must be finite");

  detail::BoxShape b{centre, half_extents, std::cos(yaw_rad), std::sin(yaw_rad)};
  const double ex = std::fabs(b.cos_yaw) * half_extents.x + std::fabs(b.sin_yaw) * half_extents.y;
  const double ey = std::fabs(b.sin_yaw) * half_extents.x + std::fabs(b.cos_yaw) * half_extents.y;
  const Vec3 ext{ex, ey, half_extents.z};

  fcl::Transform3d pose = fcl::Transform3d::Identity();
  pose.translation() = detail::to_fcl(centre);
  // Same rotation the closed form uses (u = (cos, sin, 0), v = (-sin, cos, 0)).
  pose.linear() << b.cos_yaw, -b.sin_yaw, 0.0, b.sin_yaw, b.cos_yaw, 0.0, 0.0, 0.0, 1.0;
  auto geometry =
      std::make_shared<fcl::Boxd>(2.0 * half_extents.x, 2.0 * half_extents.y, 2.0 * half_extents.z);
  const auto slot = static_cast<std::uint32_t>(impl_->boxes.size());
  impl_->boxes.push_back(b);
  return impl_->add(ShapeKind::kBox, slot, {centre - ext, centre + ext}, std::move(geometry), pose);
}

std::uint32_t StaticScenery::add_cylinder(Vec3 centre, double radius, double half_height) {
  if (!is_finite(centre)) fail("add_cylinder", "centre must be finite, got " + describe(centre));
  if (!positive_finite(radius)) fail("add_cylinder", "radius must be finite and > 0");
  if (!positive_finite(half_height)) fail("add_cylinder", "half_height must be finite and > 0");

  fcl::Transform3d pose = fcl::Transform3d::Identity();
  pose.translation() = detail::to_fcl(centre);
  auto geometry = std::make_shared<fcl::Cylinderd>(radius, 2.0 * half_height);  // along local z
  const auto slot = static_cast<std::uint32_t>(impl_->cylinders.size());
  impl_->cylinders.push_back({centre, radius, half_height});
  const Vec3 ext{radius, radius, half_height};
  return impl_->add(ShapeKind::kCylinder, slot, {centre - ext, centre + ext}, std::move(geometry),
                    pose);
}

std::uint32_t StaticScenery::add_mesh(std::vector<Vec3> vertices,
                                      std::vector<std::array<std::uint32_t, 3>> triangles) {
  if (vertices.empty()) fail("add_mesh", "mesh has no vertices");
  if (triangles.empty()) fail("add_mesh", "mesh has no triangles");
  if (vertices.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()) ||
      triangles.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    fail("add_mesh", "mesh too large");
  }
  Aabb box{vertices[0], vertices[0]};
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Vec3& v = vertices[i];
    if (!is_finite(v)) {
      fail("add_mesh", "vertex " + std::to_string(i) + " is not finite: " + describe(v));
    }
    box.lo = {std::min(box.lo.x, v.x), std::min(box.lo.y, v.y), std::min(box.lo.z, v.z)};
    box.hi = {std::max(box.hi.x, v.x), std::max(box.hi.y, v.y), std::max(box.hi.z, v.z)};
  }
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const auto& t = triangles[i];
    for (std::uint32_t k : t) {
      if (k >= vertices.size()) {
        fail("add_mesh", "triangle " + std::to_string(i) + " uses vertex index " +
                             std::to_string(k) + " but the mesh has " +
                             std::to_string(vertices.size()) + " vertices");
      }
    }
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      fail("add_mesh", "triangle " + std::to_string(i) + " repeats a vertex index");
    }
    const Vec3 e1 = vertices[t[1]] - vertices[t[0]];
    const Vec3 e2 = vertices[t[2]] - vertices[t[0]];
    // Zero-area (or numerically zero-area: sine of the corner angle below 1e-12) triangles have no
    // normal and break both FCL's narrowphase and the vertical ray test.
    if (!(length(cross(e1, e2)) > 1e-12 * length(e1) * length(e2))) {
      fail("add_mesh", "triangle " + std::to_string(i) + " has zero area");
    }
  }

  std::vector<fcl::Vector3d> points;
  points.reserve(vertices.size());
  for (const Vec3& v : vertices) points.push_back(detail::to_fcl(v));
  std::vector<fcl::Triangle> tris;
  tris.reserve(triangles.size());
  for (const auto& t : triangles) tris.emplace_back(t[0], t[1], t[2]);
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  if (model->beginModel(static_cast<int>(tris.size()), static_cast<int>(points.size())) !=
          fcl::BVH_OK ||
      model->addSubModel(points, tris) != fcl::BVH_OK || model->endModel() != fcl::BVH_OK) {
    fail("add_mesh", "FCL could not build the mesh BVH");
  }

  const auto slot = static_cast<std::uint32_t>(impl_->meshes.size());
  impl_->meshes.push_back({std::move(vertices), std::move(triangles)});
  return impl_->add(ShapeKind::kMesh, slot, box, std::move(model), fcl::Transform3d::Identity());
}

void StaticScenery::build() {
  auto manager = std::make_unique<fcl::DynamicAABBTreeCollisionManagerd>();
  std::vector<fcl::CollisionObjectd*> objects;
  objects.reserve(impl_->shapes.size());
  for (auto& r : impl_->shapes) objects.push_back(r.proxy.get());
  if (!objects.empty()) manager->registerObjects(objects);
  manager->setup();
  impl_->manager = std::move(manager);
  impl_->built = true;
}

bool StaticScenery::built() const { return impl_->built; }
std::size_t StaticScenery::size() const { return impl_->shapes.size(); }

ShapeKind StaticScenery::shape_kind(std::uint32_t shape) const {
  if (shape >= impl_->shapes.size())
    throw std::out_of_range("StaticScenery::shape_kind: no such shape");
  return impl_->shapes[shape].kind;
}

Aabb StaticScenery::aabb(std::uint32_t shape) const {
  if (shape >= impl_->shapes.size()) throw std::out_of_range("StaticScenery::aabb: no such shape");
  return impl_->shapes[shape].aabb;
}

Aabb StaticScenery::bounds() const { return impl_->bounds; }

void StaticScenery::query(const Capsule& mover, std::vector<SceneryContact>& out) const {
  impl_->require_built("query");
  detail::validate_mover(mover, "StaticScenery::query");
  detail::QueryScratch& s = detail::query_scratch();
  impl_->gather(detail::capsule_aabb(mover), s);
  const bool upright = detail::is_upright(mover);
  for (const std::uint32_t i : s.candidates) {
    const detail::SignedPenetration p = impl_->penetration(i, mover, upright, s);
    if (p.depth > 0.0) out.push_back({i, p.depth, p.normal});
  }
}

void StaticScenery::query(const UprightCapsule& mover, std::vector<SceneryContact>& out) const {
  query(to_capsule(mover), out);
}

bool StaticScenery::any_aabb_near(const Vec3& lo, const Vec3& hi) const {
  impl_->require_built("any_aabb_near");
  if (impl_->shapes.empty()) return false;
  detail::QueryScratch& s = detail::query_scratch();
  set_probe(s, inflate({lo, hi}));
  bool found = false;
  impl_->manager->collide(s.probe.get(), &found, &any_callback);
  return found;
}

}  // namespace throng::geom
