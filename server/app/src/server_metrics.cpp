#include "throng/server/server_metrics.h"

#include <string>

namespace throng::server {

namespace {
// Tick and phase durations: 0.1 ms .. ~3.3 s in factors of 2, so a 33 ms period falls in the
// middle of the range and both fast ticks and stalls are resolved.
std::vector<double> duration_buckets() { return admin::exponential_buckets(0.0001, 2.0, 16); }

admin::Histogram& world_phase(admin::MetricsRegistry& r, const char* phase) {
  return r.histogram("throng_world_phase_seconds", "Wall time of a phase of the world's step.", duration_buckets(),
                     {{"phase", phase}});
}
}  // namespace

ServerMetrics::ServerMetrics(admin::MetricsRegistry& r)
    : ticks(r.counter("throng_ticks_total", "Simulation ticks run.")),
      overruns(r.counter("throng_tick_overruns_total", "Ticks that ended after the next tick's deadline.")),
      skipped_ticks(r.counter("throng_ticks_skipped_total", "Ticks given up after a stall longer than the catch-up bound.")),
      tick_seconds(r.histogram("throng_tick_duration_seconds", "Wall time of a whole tick (simulate and publish).", duration_buckets())),
      phase_seconds_step(r.histogram("throng_tick_phase_seconds", "Wall time of a tick phase.", duration_buckets(), {{"phase", "step"}})),
      phase_seconds_publish(r.histogram("throng_tick_phase_seconds", "Wall time of a tick phase.", duration_buckets(), {{"phase", "publish"}})),
      clients(r.gauge("throng_clients", "Connected clients.")),
      bodies(r.gauge("throng_bodies", "Movable bodies in the world.")),
      joins_accepted(r.counter("throng_joins_total", "Join requests, by result.", {{"result", "accepted"}})),
      joins_refused(r.counter("throng_joins_total", "Join requests, by result.", {{"result", "refused"}})),
      joins_foreign(r.counter("throng_joins_total", "Join requests, by result.", {{"result", "foreign_participant"}})),
      param_not_operator(r.counter("throng_param_updates_total", "Operator parameter/policy changes, by result.",
                                   {{"result", "not_an_operator"}})),
      participants_refused(r.counter("throng_participants_refused_total",
                                     "DDS Security: authentication failures of remote participants (foreign CA, expired "
                                     "certificate, permissions that do not verify); a refused participant retries.")),
      leaves(r.counter("throng_client_departures_total", "Clients that left, by how.", {{"how", "left"}})),
      timeouts(r.counter("throng_client_departures_total", "Clients that left, by how.", {{"how", "timed_out"}})),
      commands_accepted(r.counter("throng_commands_accepted_total", "Client commands accepted and applied.")),
      input_queue_dropped(r.counter("throng_input_queue_dropped_total", "Inputs dropped because the input queue was full (a flood).")),
      param_updates_applied(r.counter("throng_param_updates_total", "Operator parameter/policy changes, by result.", {{"result", "applied"}})),
      param_updates_rejected(r.counter("throng_param_updates_total", "Operator parameter/policy changes, by result.", {{"result", "rejected"}})),
      snapshot_samples(r.counter("throng_snapshot_samples_total", "Snapshot samples published (one per client per tick).")),
      snapshot_bytes(r.counter("throng_snapshot_bytes_total", "Serialized snapshot payload bytes published.")),
      snapshot_poses(r.counter("throng_snapshot_poses_total", "Object poses carried by published snapshots.")),
      other_samples(r.counter("throng_other_samples_total", "Samples published on the other topics (match info, replies, stats).")),
      other_bytes(r.counter("throng_other_bytes_total", "Serialized payload bytes published on the other topics.")),
      push_events(r.counter("throng_push_events_total", "Contacts the solver pushed apart.")),
      contacts_samples(r.counter("throng_contacts_samples_total", "Contact-pairs debug samples published (clients that asked).")),
      contacts_bytes(r.counter("throng_contacts_bytes_total", "Serialized contact-pairs payload bytes published.")),
      contacts_refused(r.counter("throng_contacts_refused_total",
                                 "Commands asking for contact pairs the channel had no room for (the command still applied).")),
      view_error_max_m(r.gauge("throng_view_error_max_meters", "Largest distance between an object and a client's copy of it, last tick.")),
      state_hash_low32(r.gauge("throng_state_hash_low32", "Low 32 bits of the last tick's world state hash (determinism checks).")),
      log_backlog_ticks(r.gauge("throng_matchlog_backlog_ticks", "Ticks appended to the match log but not yet written.")),
      log_bytes(r.gauge("throng_matchlog_bytes", "Size of the match log so far.")),
      log_ticks_dropped(r.counter("throng_matchlog_ticks_dropped_total", "Ticks the match log lost (disk too slow or I/O error).")),
      log_keyframes_dropped(r.counter("throng_matchlog_keyframes_dropped_total",
                                      "World keyframes the match log skipped because its writer was behind (seeking gets slower).")),
      log_write_errors(r.counter("throng_log_write_errors_total",
                                 "Match log write or fsync errors (disk full, file too large, I/O error). The log stops "
                                 "at the first; the match goes on and /readyz says degraded.")),
      world_phase_move(world_phase(r, "move")),
      world_phase_params(world_phase(r, "params")),
      world_phase_search(world_phase(r, "search")),
      world_phase_solve(world_phase(r, "solve")),
      world_searches(r.counter("throng_world_pair_searches_total",
                               "Ticks whose step searched for pairs (the others reused a kept pair list).")),
      world_second_searches(r.counter("throng_world_second_searches_total",
                                      "Ticks whose solve moved a body beyond the contact margin, so the step searched "
                                      "and solved again.")),
      world_capped_bodies(r.counter("throng_world_capped_bodies_total",
                                    "Bodies that hit the per-body candidate cap, summed over ticks (pairs left out).")),
      world_tunnel_clamps(r.counter("throng_world_tunnel_clamps_total", "Fast moves shortened by the swept test.")),
      world_pile_relief_bodies(r.counter("throng_world_pile_relief_bodies_total",
                                         "Bodies laid out afresh from a degenerate pile (bodies at one point).")),
      world_candidate_pairs(r.gauge("throng_world_candidate_pairs", "Pairs the last step considered (within contact range plus margin).")),
      world_solver_max_pen(r.gauge("throng_world_solver_max_penetration_ratio",
                                   "Deepest overlap the last step's final sweep met, over the smaller radius.")) {
  for (std::size_t i = 0; i < match::kRejectReasonCount; ++i)
    commands_rejected[i] = &r.counter("throng_commands_rejected_total", "Client commands rejected, by reason.",
                                      {{"reason", match::to_string(static_cast<match::RejectReason>(i))}});
}

void ServerMetrics::observe_step(const StepStats& s) {
  world_phase_move.observe(s.move_us * 1e-6);
  world_phase_params.observe(s.params_us * 1e-6);
  world_phase_search.observe(s.broadphase_us * 1e-6);
  world_phase_solve.observe(s.solve_us * 1e-6);
  if (s.pair_list_reused == 0) world_searches.inc();
  world_second_searches.inc(s.second_search);
  world_capped_bodies.inc(s.capped_bodies);
  world_tunnel_clamps.inc(s.tunnel_clamps);
  world_pile_relief_bodies.inc(s.pile_relief_bodies);
  world_candidate_pairs.set(s.candidate_pairs);
  world_solver_max_pen.set(s.max_pen_over_radius);
}

}  // namespace throng::server
