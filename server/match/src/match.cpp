// Match: construction, the tick's phases in order, and read access.
#include "throng/match/match.h"

#include <chrono>
#include <cmath>
#include <utility>

#include "dense_order.h"
#include "match_impl.h"
#include "match_info.h"
#include "throng/params/object_params.h"
#include "throng/world/world.h"

namespace throng::match {
namespace {

scene::SceneDef with_tick_rate(scene::SceneDef s, const MatchConfig& config) {
  validate_config(config);  // before anything is built
  // The match's tick is the world's tick: one World::step per Match::tick.
  s.settings.dt_s = 1.0 / static_cast<double>(config.tick_hz);
  s.settings.threads = config.solver_threads;
  return s;
}

NpcAiSettings ai_settings(const MatchConfig& config) {
  NpcAiSettings s;
  s.speed_mps = config.npc_speed_mps;
  s.dt_s = 1.0 / static_cast<double>(config.tick_hz);
  return s;
}

double elapsed_us(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::micro>(b - a).count();
}

}  // namespace

Match::Impl::Impl(const scene::SceneDef& scene_in, const MatchConfig& config_in, std::string id)
    : config(config_in),
      match_id(std::move(id)),
      scene(with_tick_rate(scene_in, config_in)),
      table(scene::load_param_table(scene.params)),
      built(scene::build_scene(scene)),
      ai(ai_settings(config)),
      snapshots(config.interest),
      pool(config.worker_threads),
      scratches(pool.threads()),
      worker_totals(pool.threads()) {
  timeout_ticks = static_cast<std::uint64_t>(std::llround(config.client_timeout_s * config.tick_hz));
  if (const params::ObjectParams* player = table.find_archetype("player")) player_importance = player->importance;

  built.world.set_push_events_recorded(config.push_events);
  const World& w = world();
  const std::size_t n = w.body_count();
  id_values.resize(n);
  yaw.assign(n, 0.0f);
  controller.assign(n, 0u);
  for (std::size_t d = 0; d < n; ++d) {
    const ObjectId oid = w.id_at(d);
    id_values[d] = oid.value;
    body_slots = std::max<std::size_t>(body_slots, oid.index() + 1);
  }
  // The roster is in the dense order at construction.
  roster_of_slot.assign(body_slots, kNoDense);
  for (std::size_t d = 0; d < n; ++d) roster_of_slot[w.id_at(d).index()] = static_cast<std::uint32_t>(d);
  contacts_granted.reserve(config.contacts.max_clients);
  ai.init(w);
  info = build_match_info(MatchInfoSource{scene, table, w, built.scenery_ids, built.body_ids, config, match_id});
  compute_checkpoint_hashes();
}

void Match::Impl::follow_reorder() {
  const std::span<const std::uint32_t> perm = world().last_reorder();
  if (perm.empty()) return;
  ai.apply_reorder(perm);
  apply_permutation(yaw, perm, scratch_f32);
  apply_permutation(controller, perm, scratch_u32);
  apply_permutation(id_values, perm, scratch_u32);
}

std::uint32_t Match::Impl::dense_of(ObjectId id) const {
  const std::optional<std::size_t> d = world().dense_index(id);
  return d ? static_cast<std::uint32_t>(*d) : kNoDense;
}

Match::Match(const scene::SceneDef& scene, const MatchConfig& config, std::string match_id)
    : impl_(std::make_unique<Impl>(scene, config, std::move(match_id))) {}

Match::~Match() = default;

InputQueue& Match::inputs() { return impl_->queue; }
const InputQueue& Match::inputs() const { return impl_->queue; }

const TickReport& Match::tick(Outbox& out) {
  using clock = std::chrono::steady_clock;
  Impl& m = *impl_;
  out.clear();
  m.report = TickReport{};
  TickReport& r = m.report;
  const std::uint64_t tick = m.ticks + 1;  // the number of the tick being simulated
  r.tick = tick;

  const auto t0 = clock::now();
  m.queue.drain(m.inputs);
  const auto t1 = clock::now();
  m.apply_joins(tick, out);
  m.apply_commands(tick);
  m.apply_params(tick, out);
  m.apply_timeouts(tick, out);
  m.feed_cameras();
  const auto t2 = clock::now();
  m.ai.update(m.world(), m.controller, m.yaw);
  const auto t3 = clock::now();
  r.world = m.world().step();
  m.follow_reorder();
  r.push_events = static_cast<std::uint32_t>(m.world().push_events().size());
  r.state_hash = m.world().state_hash();
  m.ticks = tick;
  const auto t4 = clock::now();
  m.build_snapshots(tick, out);
  m.build_contacts(tick, out);
  m.clients.forget_departed();  // this tick's departures are in its outbox; the match holds connected clients only
  const auto t5 = clock::now();

  if (m.info_dirty) {
    out.match_info_changed = true;
    m.info_dirty = false;
  }
  r.drain_us = elapsed_us(t0, t1);
  r.apply_us = elapsed_us(t1, t2);
  r.ai_us = elapsed_us(t2, t3);
  r.step_us = elapsed_us(t3, t4);
  r.snapshots_us = elapsed_us(t4, t5);
  r.total_us = elapsed_us(t0, t5);
  return r;
}

void Match::begin_shutdown() {
  Impl& m = *impl_;
  m.shutting_down = true;
  if (m.info.state != protocol::MatchState::ended) {
    m.info.state = protocol::MatchState::ended;
    m.info_dirty = true;
  }
}

const protocol::MatchInfo& Match::match_info() const { return impl_->info; }
std::uint64_t Match::tick_index() const { return impl_->ticks; }
void Match::set_snapshot_sink(SnapshotSink sink) { impl_->sink = std::move(sink); }
const TickInputs& Match::last_inputs() const { return impl_->inputs; }
std::uint64_t Match::state_hash() const { return impl_->world().state_hash(); }
std::uint32_t Match::client_count() const { return static_cast<std::uint32_t>(impl_->clients.connected_count()); }

std::vector<ClientSummary> Match::clients() const {
  std::vector<ClientSummary> out;
  for (std::uint32_t id : impl_->clients.connected_ids()) {
    const ClientRecord* c = impl_->clients.find(id);
    out.push_back(ClientSummary{c->id, c->entity.value, c->name, c->last_applied_sequence, c->joined_tick,
                                c->commands_accepted, c->commands_rejected, c->partition});
  }
  return out;
}

std::optional<std::uint8_t> Match::routed_faction() const { return match::routed_faction(impl_->ai.groups()); }

std::uint32_t Match::npc_count() const {
  return static_cast<std::uint32_t>(impl_->world().body_count() - impl_->clients.connected_count());
}

const std::array<std::uint64_t, kRejectReasonCount>& Match::rejected_by_reason() const { return impl_->rejected; }
std::uint64_t Match::commands_accepted_total() const { return impl_->accepted_total; }
const MatchConfig& Match::config() const { return impl_->config; }
const World& Match::world() const { return impl_->world(); }
void Match::save_checkpoint(std::vector<std::uint8_t>& out) const { impl_->save_checkpoint(out, SaveOptions{}); }
void Match::save_checkpoint(std::vector<std::uint8_t>& out, SaveOptions options) const {
  impl_->save_checkpoint(out, options);
}
void Match::restore_checkpoint(std::span<const std::uint8_t> bytes) { restore_checkpoint(bytes, RestoreOptions{}); }

}  // namespace throng::match
