// FCL narrowphase for the cases without a closed form here: tilted movers (against boxes and
// cylinders) and meshes.
//
// Solver choice: libccd (GST_LIBCCD), whose penetration is MPR. FCL 0.7's own GJK/EPA
// (GST_INDEP) returns negative penetration depths for capsule-box/-cylinder/-triangle, and for a
// rotated capsule a normal still expressed in the capsule's frame, so it is not used.
#include <cmath>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>

#include "fcl_shapes.h"
#include "scenery_impl.h"

namespace throng::geom::detail {

SignedPenetration fcl_penetration(const ShapeRecord& shape, const Capsule& mover,
                                  QueryScratch& s) {
  // Geometry on the stack: constructing an FCL shape does not allocate.
  const fcl::Capsuled capsule(mover.radius, capsule_length(mover));
  const fcl::Transform3d pose = capsule_pose(mover);

  s.request.enable_contact = true;
  s.request.gjk_solver_type = fcl::GST_LIBCCD;
  s.request.num_max_contacts = 1;
  if (shape.kind == ShapeKind::kMesh) {
    // One contact per touched triangle, so that the deepest one can be picked below.
    s.request.num_max_contacts =
        static_cast<std::size_t>(static_cast<const fcl::BVHModel<fcl::OBBRSSd>&>(*shape.geometry)
                                     .num_tris);
  }
  s.result.clear();  // keeps the contact vector's capacity
  fcl::collide(&capsule, pose, shape.geometry.get(), shape.pose, s.request, s.result);

  SignedPenetration best{0.0, {0.0, 0.0, 1.0}};
  bool found = false;
  std::intptr_t best_primitive = 0;
  for (std::size_t k = 0; k < s.result.numContacts(); ++k) {
    const fcl::Contactd& c = s.result.getContact(k);
    const double depth = c.penetration_depth;
    if (!(depth > 0.0) || !c.normal.allFinite()) continue;
    // FCL's normal points from its o1 to its o2. For shape pairs o1 is our capsule; for meshes
    // FCL reports the mesh as o1 whatever the argument order, so check rather than assume.
    const bool mover_first = c.o1 == &capsule;
    const fcl::Vector3d out = mover_first ? fcl::Vector3d(-c.normal) : c.normal;
    const double n = out.norm();
    if (!(n > 0.0)) continue;
    const std::intptr_t primitive = mover_first ? c.b2 : c.b1;  // triangle id for meshes
    // Deepest contact wins; equal depths go to the lower triangle id (FCL's visiting order is
    // deterministic anyway, but this keeps the rule explicit).
    if (!found || depth > best.depth || (depth == best.depth && primitive < best_primitive)) {
      found = true;
      best.depth = depth;
      best.normal = from_fcl(out / n);
      best_primitive = primitive;
    }
  }
  return best;
}

}  // namespace throng::geom::detail
