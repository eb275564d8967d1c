// Mover vs triangle mesh: FCL's BVH finds the triangles the capsule overlaps (boolean test only),
// the contact itself is computed here in closed form.
//
// Why not FCL's contacts: per triangle FCL runs libccd MPR, whose push-out follows the line
// between the shapes' interior points rather than the shortest way out. Against a single triangle
// that often means sliding sideways off it, straight into its neighbour (seen in testing: a core
// 0.1 m through a wall got a mostly tangential normal). Here each overlapped triangle gives:
//  * core segment clear of the triangle: depth = radius - distance, along the closest points;
//  * core touching or piercing it: out through the triangle's plane on whichever side is nearer,
//    so a mesh behaves like a two-sided surface.
// The deepest triangle is the mesh's contact (ties: lowest triangle index).
#include <fcl/narrowphase/collision.h>

#include <algorithm>
#include <cmath>

#include "fcl_shapes.h"
#include "scenery_impl.h"
#include "segment_triangle.h"
#include "throng/geometry/capsule_contact.h"

namespace throng::geom::detail {
namespace {

SignedPenetration triangle_contact(const Capsule& m, const Vec3& a, const Vec3& b, const Vec3& c) {
  const SegmentTriangleClosest st = closest_segment_triangle(m.p0, m.p1, a, b, c);
  if (!st.pierces && st.distance > kCoreTouchRelTol * st.scale) {
    const Vec3 d = st.on_segment - st.on_triangle;
    return {m.radius - st.distance, {d.x / st.distance, d.y / st.distance, d.z / st.distance}};
  }
  const Vec3 n = cross(b - a, c - a);
  const double len = length(n);
  const Vec3 u{n.x / len, n.y / len, n.z / len};  // add_mesh rejected zero-area triangles
  const double s0 = dot(m.p0 - a, u);
  const double s1 = dot(m.p1 - a, u);
  const double front = m.radius - std::min(s0, s1);  // move along +u until both ends clear
  const double back = m.radius + std::max(s0, s1);   // or along -u
  if (front <= back) return {front, u};
  return {back, -u};
}

}  // namespace

// FCL's overlap test (libccd MPR, 1e-6 tolerance) misses overlaps of a few 1e-9 m; candidates are
// picked with a slightly fatter capsule so every truly overlapped triangle is examined.
constexpr double kCandidateMargin = 1e-5;

SignedPenetration mesh_penetration(const ShapeRecord& shape, const MeshShape& mesh,
                                   const Capsule& mover, QueryScratch& s) {
  const fcl::Capsuled capsule(mover.radius + kCandidateMargin, capsule_length(mover));
  const fcl::Transform3d pose = capsule_pose(mover);
  s.request.enable_contact = false;  // only which triangles overlap
  s.request.gjk_solver_type = fcl::GST_LIBCCD;
  s.request.num_max_contacts = mesh.triangles.size();
  s.result.clear();
  fcl::collide(&capsule, pose, shape.geometry.get(), shape.pose, s.request, s.result);

  SignedPenetration best{0.0, {0.0, 0.0, 1.0}};
  std::intptr_t best_triangle = -1;
  for (std::size_t k = 0; k < s.result.numContacts(); ++k) {
    const fcl::Contactd& c = s.result.getContact(k);
    const std::intptr_t id = c.o1 == &capsule ? c.b2 : c.b1;  // FCL puts the mesh first
    if (id < 0 || static_cast<std::size_t>(id) >= mesh.triangles.size()) continue;
    const auto& t = mesh.triangles[static_cast<std::size_t>(id)];
    const SignedPenetration p =
        triangle_contact(mover, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
    if (p.depth > best.depth || (p.depth == best.depth && p.depth > 0.0 && id < best_triangle)) {
      best = p;
      best_triangle = id;
    }
  }
  return best;
}

}  // namespace throng::geom::detail
