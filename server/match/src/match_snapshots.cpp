// The snapshots phase: the interest grid is indexed once with this tick's bodies, then one
// Snapshot per connected client, in client-id order, written into the outbox's reused elements.
#include <algorithm>

#include "match_impl.h"
#include "throng/world/world.h"

namespace throng::match {

void Match::Impl::build_snapshots(std::uint64_t tick, Outbox& out) {
  const World& w = world();
  const auto xs = w.pos_x();
  const auto ys = w.pos_y();
  const auto zs = w.pos_z();
  snapshots.index(BodyView{id_values, xs, ys, zs, yaw}, tick);
  const auto ids = clients.connected_ids();
  if (out.snapshots.size() < ids.size()) out.snapshots.resize(ids.size());
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const ClientRecord& c = *clients.find(ids[k]);
    protocol::Snapshot& s = out.snapshots[k];
    const std::uint32_t d = dense_of(c.entity);
    s.client_id = c.id;
    s.tick = tick;
    s.last_applied_sequence = c.last_applied_sequence;
    s.last_applied_tick = c.last_applied_tick;
    s.entity = c.entity.value;
    s.entity_x = static_cast<float>(xs[d]);
    s.entity_y = static_cast<float>(ys[d]);
    s.entity_z = static_cast<float>(zs[d]);
    s.entity_yaw = yaw[d];
    const Vec3 cam = camera_of(c);
    const BuildStats& st = snapshots.build(c.id, cam.x, cam.y, s);
    report.snapshot_poses += st.sent;
    report.view_error_max_m = std::max(report.view_error_max_m, st.view_error_max_m);
  }
  out.snapshot_count = ids.size();
}

}  // namespace throng::match
