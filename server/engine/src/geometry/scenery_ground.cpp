// StaticScenery::ground_height: the highest walkable top under a point.
#include <cmath>
#include <limits>

#include "scenery_impl.h"

namespace throng::geom {
namespace {

// z where the vertical line through (x, y) crosses triangle (a, b, c), if it does (edges
// included). Vertical triangles (zero area in xy) have no single crossing height: skipped.
bool vertical_line_hit(const Vec3& a, const Vec3& b, const Vec3& c, double x, double y, double& z) {
  // Signed areas of the sub-triangles opposite each vertex (barycentric numerators).
  const double wa = (b.x - x) * (c.y - y) - (c.x - x) * (b.y - y);
  const double wb = (c.x - x) * (a.y - y) - (a.x - x) * (c.y - y);
  const double wc = (a.x - x) * (b.y - y) - (b.x - x) * (a.y - y);
  const bool all_nonneg = wa >= 0.0 && wb >= 0.0 && wc >= 0.0;
  const bool all_nonpos = wa <= 0.0 && wb <= 0.0 && wc <= 0.0;
  const double sum = wa + wb + wc;
  if (!(all_nonneg || all_nonpos) || sum == 0.0) return false;
  z = (wa * a.z + wb * b.z + wc * c.z) / sum;
  return true;
}

}  // namespace

double StaticScenery::ground_height(double x, double y, double z_feet) const {
  impl_->require_built("ground_height");
  const double limit = z_feet + kStepTolerance;
  double best = 0.0 <= limit ? 0.0 : -std::numeric_limits<double>::infinity();  // ground plane
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(limit) || impl_->shapes.empty() ||
      limit < impl_->bounds.lo.z) {
    return std::isfinite(best) ? best : 0.0;
  }

  detail::QueryScratch& s = detail::query_scratch();
  impl_->gather({{x, y, impl_->bounds.lo.z}, {x, y, limit}}, s);
  for (const std::uint32_t i : s.candidates) {
    const detail::ShapeRecord& r = impl_->shapes[i];
    switch (r.kind) {
      case ShapeKind::kBox: {
        const detail::BoxShape& b = impl_->boxes[r.slot];
        const double rx = x - b.centre.x;
        const double ry = y - b.centre.y;
        const double lx = rx * b.cos_yaw + ry * b.sin_yaw;
        const double ly = ry * b.cos_yaw - rx * b.sin_yaw;
        const double top = b.centre.z + b.half.z;
        if (std::fabs(lx) <= b.half.x && std::fabs(ly) <= b.half.y && top <= limit && top > best) {
          best = top;
        }
        break;
      }
      case ShapeKind::kCylinder: {
        const detail::CylinderShape& c = impl_->cylinders[r.slot];
        const double rx = x - c.centre.x;
        const double ry = y - c.centre.y;
        const double top = c.centre.z + c.half_height;
        if (rx * rx + ry * ry <= c.radius * c.radius && top <= limit && top > best) best = top;
        break;
      }
      case ShapeKind::kMesh: {
        // Linear in the mesh's triangles: scenery meshes are small props and ramps; large
        // terrain should be split into several meshes so the broadphase does the culling.
        const detail::MeshShape& m = impl_->meshes[r.slot];
        for (const auto& t : m.triangles) {
          double z = 0.0;
          if (vertical_line_hit(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], x, y, z) &&
              z <= limit && z > best) {
            best = z;
          }
        }
        break;
      }
    }
  }
  return std::isfinite(best) ? best : 0.0;
}

}  // namespace throng::geom
