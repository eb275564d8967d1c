// Fixed scenery inside the tick: which bodies are near it, their separating planes (the patent's
// virtual planes against fixed bodies, including soft ones), and a last check after the solve.
#include <algorithm>
#include <cmath>
#include <limits>

#include "broadphase/cell_key.h"
#include "throng/params/soft_push.h"
#include "world/world_impl.h"

namespace throng {
namespace {

std::uint64_t scenery_cell_key(double x, double y, double inv_cell) {
  return detail::packed_cell_key(detail::cell_coord(x, inv_cell), detail::cell_coord(y, inv_cell));
}

geom::Capsule body_capsule(double x, double y, double z, double hh, double r) {
  return geom::Capsule{{x, y, z - hh}, {x, y, z + hh}, r};
}

// A grounded body cannot leave a fixed shape upwards. When the shortest way out is vertical:
//  - centre above the shape's top: it stands on the shape (a ledge): support, not a contact;
//  - otherwise it is embedded (spawned or teleported inside): it gets a horizontal way out, away
//    from the shape's centre, far enough to clear the shape's box. Conservative for boxes and
//    cylinders; deterministic (+x when the centres coincide).
// Returns false when the contact is support and must be ignored.
bool grounded_contact(const geom::Aabb& box, double x, double y, double z, double r, geom::SceneryContact& c) {
  const double h2 = c.normal.x * c.normal.x + c.normal.y * c.normal.y;
  if (h2 >= 0.09) return true;
  if (z >= box.hi.z) return false;
  double ux = x - 0.5 * (box.lo.x + box.hi.x), uy = y - 0.5 * (box.lo.y + box.hi.y);
  const double len = std::sqrt(ux * ux + uy * uy);
  if (len > 1e-12) { ux /= len; uy /= len; } else { ux = 1.0; uy = 0.0; }
  // Distance along u from the body's centre to where the box ends (ray exit), plus the radius.
  double exit = std::numeric_limits<double>::infinity();
  if (ux > 0.0) exit = std::min(exit, (box.hi.x - x) / ux);
  if (ux < 0.0) exit = std::min(exit, (box.lo.x - x) / ux);
  if (uy > 0.0) exit = std::min(exit, (box.hi.y - y) / uy);
  if (uy < 0.0) exit = std::min(exit, (box.lo.y - y) / uy);
  c.normal = {ux, uy, 0.0};
  c.depth = std::max(0.0, exit) + r;
  return true;
}

}  // namespace

// Cells (scenery_cell_m square) that lie within reach of any fixed shape. Only bodies standing in
// such a cell are queried against FCL, so a crowd in an open field pays nothing for the scenery.
// Reach: a body's radius and margin plus one metre of travel within a tick (step() passes
// max_body_reach_m + 1 whenever a larger body appears; a restored checkpoint passes the saved reach).
void World::Impl::rebuild_scenery_cells(double reach) {
  if (scenery_dirty) scenery.build();
  scenery_dirty = false;
  scenery_cells.clear();
  scenery_bitmap.clear();
  scenery_reach_m = reach;
  const double inv = 1.0 / scenery_cell_m;
  std::int64_t bx0 = 0, by0 = 0, bx1 = -1, by1 = -1;
  for (std::uint32_t s = 0; s < scenery.size(); ++s) {
    const geom::Aabb box = scenery.aabb(s);
    const std::int64_t x0 = detail::cell_coord(box.lo.x - reach, inv), x1 = detail::cell_coord(box.hi.x + reach, inv);
    const std::int64_t y0 = detail::cell_coord(box.lo.y - reach, inv), y1 = detail::cell_coord(box.hi.y + reach, inv);
    if (bx1 < bx0) {
      bx0 = x0, bx1 = x1, by0 = y0, by1 = y1;
    } else {
      bx0 = std::min(bx0, x0), bx1 = std::max(bx1, x1), by0 = std::min(by0, y0), by1 = std::max(by1, y1);
    }
    for (std::int64_t cy = y0; cy <= y1; ++cy) {
      for (std::int64_t cx = x0; cx <= x1; ++cx) scenery_cells.push_back(detail::packed_cell_key(cx, cy));
    }
  }
  std::sort(scenery_cells.begin(), scenery_cells.end());
  scenery_cells.erase(std::unique(scenery_cells.begin(), scenery_cells.end()), scenery_cells.end());
  // A bitmap of at most 4 Mi cells (a 4 km square of 2 m cells): enough for any one battlefield.
  constexpr std::int64_t kMaxBitmapCells = std::int64_t{1} << 22;
  if (scenery_cells.empty() || bx1 - bx0 + 1 > kMaxBitmapCells || by1 - by0 + 1 > kMaxBitmapCells ||
      (bx1 - bx0 + 1) * (by1 - by0 + 1) > kMaxBitmapCells) {
    return;
  }
  scenery_bx0 = bx0, scenery_by0 = by0, scenery_bw = bx1 - bx0 + 1, scenery_bh = by1 - by0 + 1;
  scenery_bitmap.assign(static_cast<std::size_t>(scenery_bw * scenery_bh), 0);
  for (const std::uint64_t key : scenery_cells) {
    const std::int64_t cx = static_cast<std::int64_t>(key & 0xFFFFFFFFu) - (std::int64_t{1} << 31);
    const std::int64_t cy = static_cast<std::int64_t>(key >> 32) - (std::int64_t{1} << 31);
    scenery_bitmap[static_cast<std::size_t>((cy - scenery_by0) * scenery_bw + (cx - scenery_bx0))] = 1;
  }
}

// Inline here (its only callers are this file's per-body loops, four passes a tick when a tick
// solves twice): as a call it was a few percent of a battle's world step.
[[gnu::always_inline]] inline bool World::Impl::near_scenery(double x, double y) const {
  if (scenery_cells.empty()) return false;
  const double inv = 1.0 / scenery_cell_m;
  if (scenery_bitmap.empty()) {
    return std::binary_search(scenery_cells.begin(), scenery_cells.end(), scenery_cell_key(x, y, inv));
  }
  const std::int64_t cx = detail::cell_coord(x, inv) - scenery_bx0, cy = detail::cell_coord(y, inv) - scenery_by0;
  if (cx < 0 || cy < 0 || cx >= scenery_bw || cy >= scenery_bh) return false;
  return scenery_bitmap[static_cast<std::size_t>(cy * scenery_bw + cx)] != 0;
}

void World::Impl::build_scenery_planes() {
  planes.clear();
  const std::size_t n = sb.size();
  std::fill(sb.plane_count.begin(), sb.plane_count.end(), 0u);
  if (scenery.size() == 0) return;
  const double margin = settings.contact_margin_m;
  for (std::size_t s = 0; s < n; ++s) {
    sb.plane_begin[s] = static_cast<std::uint32_t>(planes.size());
    if (!near_scenery(sb.x[s], sb.y[s])) continue;
    contacts.clear();
    // Inflated by the margin so a wall the crowd may push this body into is already a plane.
    scenery.query(body_capsule(sb.x[s], sb.y[s], sb.z[s], sb.hh[s], sb.r[s] + margin), contacts);
    for (geom::SceneryContact& c : contacts) {
      if (sb.grounded[s] &&
          !grounded_contact(scenery.aabb(c.shape), sb.x[s], sb.y[s], sb.z[s], sb.r[s] + margin, c)) {
        continue;
      }
      const double depth = c.depth - margin;  // > 0: penetrating now
      const double dot_now = c.normal.x * sb.x[s] + c.normal.y * sb.y[s] + c.normal.z * sb.z[s];
      double share = 1.0;
      double offset = dot_now + depth;
      const double softness = fixed_params[c.shape].softness;
      if (softness > 0.0 && depth > 0.0) {
        // Soft fixed body (FIG. 10): only a depth-dependent share of the depth is removed this tick.
        // The tick's second solve (World::step) holds the body where the first left it: the soft
        // push is made once a tick.
        share = second_solve ? 0.0 : params::soft_push_share(softness, depth, sb.r[s]);
        offset -= depth * (1.0 - share);
      }
      planes.push_back({c.normal.x, c.normal.y, c.normal.z, offset, 0.0, share, static_cast<std::uint32_t>(s),
                        fixed_ids[c.shape]});
    }
    sb.plane_count[s] = static_cast<std::uint32_t>(planes.size()) - sb.plane_begin[s];
  }
  stats.scenery_planes = static_cast<std::uint32_t>(planes.size());
}

// Planes are linearised at the start of the solve; a body that had none (it was not near a wall)
// but was pushed far during the solve, or sits at a corner the planes only approximate, is checked
// against the real shapes once more and pushed out fully. Soft bodies are left to their planes.
void World::Impl::verify_scenery_after_solve() {
  if (scenery.size() == 0) return;
  const std::size_t n = bodies.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (!near_scenery(bodies.x[i], bodies.y[i])) continue;
    contacts.clear();
    // Sweep from the tick's start so that a solve push cannot carry a body through a thin wall.
    const double dx = bodies.x[i] - start_x[i], dy = bodies.y[i] - start_y[i], dz = bodies.z[i] - start_z[i];
    const double half_r = 0.5 * bodies.r[i];
    if (dx * dx + dy * dy + dz * dz > half_r * half_r) {
      const geom::Capsule from = body_capsule(start_x[i], start_y[i], start_z[i], bodies.hh[i], bodies.r[i]);
      const double frac = scenery.first_hit_fraction(from, {dx, dy, dz});
      if (frac < 1.0) {
        bodies.x[i] = start_x[i] + dx * frac;
        bodies.y[i] = start_y[i] + dy * frac;
        bodies.z[i] = start_z[i] + dz * frac;
        ++stats.tunnel_clamps;
      }
    }
    scenery.query(body_capsule(bodies.x[i], bodies.y[i], bodies.z[i], bodies.hh[i], bodies.r[i]), contacts);
    for (geom::SceneryContact& c : contacts) {
      if (fixed_params[c.shape].softness > 0.0) continue;
      if (bodies.grounded[i] &&
          !grounded_contact(scenery.aabb(c.shape), bodies.x[i], bodies.y[i], bodies.z[i], bodies.r[i], c)) {
        continue;
      }
      double nx = c.normal.x, ny = c.normal.y, nz = c.normal.z, d = c.depth;
      if (bodies.grounded[i]) {
        const double h2 = nx * nx + ny * ny;
        d /= std::sqrt(h2);
        const double h = std::sqrt(h2);
        nx /= h; ny /= h; nz = 0.0;
      }
      bodies.x[i] += nx * d;
      bodies.y[i] += ny * d;
      bodies.z[i] += nz * d;
    }
  }
}

double World::scenery_max_penetration(std::size_t dense_index) const {
  const Impl& w = *impl_;
  if (w.scenery.size() == 0) return 0.0;
  std::vector<geom::SceneryContact> found;
  const detail::BodyStore& b = w.bodies;
  w.scenery.query(body_capsule(b.x.at(dense_index), b.y[dense_index], b.z[dense_index], b.hh[dense_index],
                               b.r[dense_index]),
                  found);
  double worst = 0.0;
  for (const geom::SceneryContact& c : found) {
    // Soft bodies are meant to be sunk into (up to their maximum sink); they are not residual error.
    if (w.fixed_params[c.shape].softness > 0.0) continue;
    worst = std::max(worst, c.depth);
  }
  return worst;
}

}  // namespace throng
