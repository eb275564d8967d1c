// The snapshots phase: the interest grid is indexed once with this tick's bodies, then one
// Snapshot per connected client, written into the outbox's reused elements (slot k = the k-th
// connected client in id order). Clients are built on the worker pool; every build reads only the
// index and writes only its own client's state and slot, so the bytes do not depend on the
// threads, and the statistics are reduced with sum/max, which do not depend on the order either.
#include <algorithm>

#include "interest_grid.h"
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
  for (auto& t : worker_totals) t = WorkerTotals{};
  for (auto& sc : scratches) snapshots.reserve(sc);  // whichever worker gets a client: no allocation

  auto build_one = [&](std::uint32_t k, unsigned worker) {
    WorkerTotals& totals = worker_totals[worker];
    if (totals.error) return;
    try {
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
      // A client without a camera looks from its entity, which nothing keeps within the coordinates
      // snapshots serve; beyond them there is nothing to see (the interest grid leaves such bodies
      // out), so the view is taken from the edge instead of failing the tick.
      const Vec3 cam = camera_of(c);
      const BuildStats& st =
          snapshots.build(c.id, std::clamp(cam.x, -detail::kMaxCoordinateM, detail::kMaxCoordinateM),
                          std::clamp(cam.y, -detail::kMaxCoordinateM, detail::kMaxCoordinateM), s, scratches[worker]);
      totals.poses += st.sent;
      totals.view_error_max_m = std::max(totals.view_error_max_m, st.view_error_max_m);
      if (sink) sink(s);
    } catch (...) {
      totals.error = std::current_exception();  // rethrown on the tick thread below
    }
  };
  pool.run(static_cast<std::uint32_t>(ids.size()), build_one);
  for (const auto& t : worker_totals) {
    if (t.error) std::rethrow_exception(t.error);
    report.snapshot_poses += t.poses;
    report.view_error_max_m = std::max(report.view_error_max_m, t.view_error_max_m);
  }
  out.snapshot_count = ids.size();
}

}  // namespace throng::match
