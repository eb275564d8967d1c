#include "throng/client_sim/bot.h"

#include <cmath>

namespace throng::client_sim {

Bot::Bot(BotConfig config, TimePoint launch)
    : config_(std::move(config)),
      behavior_(make_behavior(config_.behavior)),
      join_(config_.nonce, config_.name),
      world_(config_.world) {
  config_.nonce = join_.nonce();  // the drawn one when the config left it 0
  rng_.seed(config_.seed != 0 ? config_.seed : JoinHandshake::random_nonce());
  metrics_.on_launch(launch);
}

Bot::State Bot::state() const {
  std::lock_guard lock(mutex_);
  return join_.state();
}
std::uint32_t Bot::client_id() const {
  std::lock_guard lock(mutex_);
  return join_.reply().client_id;
}
std::uint32_t Bot::entity() const {
  std::lock_guard lock(mutex_);
  return join_.reply().entity;
}
std::string Bot::partition() const {
  std::lock_guard lock(mutex_);
  return join_.reply().snapshot_partition;
}
std::optional<TimePoint> Bot::join_sent_at() const {
  std::lock_guard lock(mutex_);
  return join_.join_sent_at();
}
std::optional<TimePoint> Bot::last_join_sent_at() const {
  std::lock_guard lock(mutex_);
  return join_.last_join_sent_at();
}
bool Bot::has_first_snapshot() const {
  std::lock_guard lock(mutex_);
  return metrics_.first_snapshot().has_value();
}

protocol::JoinRequest Bot::join_request(TimePoint now) {
  std::lock_guard lock(mutex_);
  return join_.join_request(now);
}

bool Bot::on_join_reply(const protocol::JoinReply& reply) { return on_join_reply(reply, Clock::now()); }

bool Bot::on_join_reply(const protocol::JoinReply& reply, TimePoint now) {
  std::lock_guard lock(mutex_);
  const bool accepted = join_.on_join_reply(reply);
  if (accepted) joined_at_ = now;
  return accepted;
}

void Bot::mark_timed_out() {
  std::lock_guard lock(mutex_);
  join_.mark_timed_out();
}

std::optional<protocol::JoinRequest> Bot::leave_request() {
  std::lock_guard lock(mutex_);
  return join_.leave_request();
}

void Bot::set_match(std::shared_ptr<const MatchView> match) {
  std::lock_guard lock(mutex_);
  match_ = match;
  world_.set_match(std::move(match));
}

std::optional<std::uint32_t> Bot::begin_rejoin(TimePoint now, std::chrono::milliseconds silence) {
  std::lock_guard lock(mutex_);
  if (join_.state() != State::joined) return std::nullopt;
  // Silent since the newest snapshot or, after a rejoin, since the new client was accepted (the
  // old client's snapshots do not count against it, nor the wait for the reply).
  std::optional<TimePoint> last = metrics_.last_snapshot();
  if (joined_at_ && (!last || *joined_at_ > *last)) last = joined_at_;
  if (!last || now - *last < silence) return std::nullopt;
  const std::uint32_t old = join_.reply().client_id;
  join_ = JoinHandshake(0, config_.name);  // a new nonce: the server must not see the old join again
  config_.nonce = join_.nonce();
  world_ = ClientWorld(config_.world);
  if (match_) world_.set_match(match_);
  first_pose_.reset();
  first_tick_time_.reset();
  next_sequence_ = 1;
  last_applied_sequence_ = 0;
  metrics_.on_rejoin();
  ++rejoins_;
  return old;
}

std::uint32_t Bot::rejoins() const {
  std::lock_guard lock(mutex_);
  return rejoins_;
}

void Bot::on_snapshot(const protocol::Snapshot& snap, std::size_t wire_bytes, TimePoint now) {
  std::lock_guard lock(mutex_);
  if (join_.state() != State::joined && join_.state() != State::left) return;
  if (snap.client_id != join_.reply().client_id) return;  // not ours (never expected: one partition per client)
  if (world_.tick_hz() > 0) metrics_.set_tick_ms(1000.0 / world_.tick_hz());
  metrics_.on_snapshot_received(snap.tick, wire_bytes, now);
  if (world_.apply(snap) != ClientWorld::ApplyResult::applied) return;
  last_applied_sequence_ = snap.last_applied_sequence;
  metrics_.on_applied_sequence(snap.last_applied_sequence, now);
  if (auto own = world_.own_pose()) {
    if (!first_pose_) first_pose_ = own;
  }
}

class Bot::Sink final : public CommandSink {
 public:
  Sink(Bot& bot, const ObjectState& self, TimePoint now, std::vector<protocol::Command>& out)
      : bot_(bot), self_(self), now_(now), out_(out), first_(out.size()) {}

  protocol::Command& emit(const Intent& intent, Expect expect) override {
    protocol::Command c;
    c.client_id = bot_.join_.reply().client_id;
    c.entity = bot_.join_.reply().entity;
    c.sequence = bot_.next_sequence_++;
    c.last_seen_tick = bot_.world_.newest_tick().value_or(0);
    c.move_x = intent.move_x;
    c.move_y = intent.move_y;
    c.facing_rad = intent.facing_rad;
    c.actions = intent.actions;
    c.camera_x = static_cast<float>(self_.x);
    c.camera_y = static_cast<float>(self_.y);
    c.camera_z = static_cast<float>(self_.z);
    out_.push_back(c);
    expects_.push_back(expect);
    return out_.back();
  }

  // After act(): the behavior may have changed sequences, so record what actually goes out.
  void commit() {
    for (std::size_t i = 0; i < expects_.size(); ++i)
      bot_.metrics_.on_command_sent(out_[first_ + i].sequence, expects_[i], now_);
  }

 private:
  Bot& bot_;
  const ObjectState& self_;
  TimePoint now_;
  std::vector<protocol::Command>& out_;
  std::size_t first_;
  std::vector<Expect> expects_;
};

void Bot::tick(TimePoint now, std::span<const std::uint32_t> others, std::vector<protocol::Command>& out) {
  std::lock_guard lock(mutex_);
  if (join_.state() != State::joined) return;
  const auto self = world_.own_pose();
  if (!self || !first_pose_) return;
  if (!first_tick_time_) first_tick_time_ = now;
  BehaviorContext ctx{world_,
                      join_.reply().client_id,
                      join_.reply().entity,
                      join_.reply().faction,
                      *self,
                      *first_pose_,
                      std::chrono::duration<double>(now - *first_tick_time_).count(),
                      world_.tick_hz(),
                      rng_,
                      others};
  Sink sink(*this, *self, now, out);
  behavior_->act(ctx, sink);
  sink.commit();
}

BotReport Bot::report(TimePoint now) const {
  std::lock_guard lock(mutex_);
  BotReport r;
  r.name = config_.name;
  r.behavior = config_.behavior;
  r.state = to_string(join_.state());
  if (join_.state() == State::refused) r.refused_reason = join_.reply().reason;
  r.client_id = join_.reply().client_id;
  r.entity = join_.reply().entity;
  r.faction = join_.reply().faction;
  r.commands = metrics_.commands();
  r.snapshots = metrics_.snapshots();
  r.decode_errors = world_.malformed_count();
  r.last_applied_sequence = last_applied_sequence_;
  r.last_tick = world_.newest_tick().value_or(0);
  r.join_ms = metrics_.join_ms();
  if (auto first = metrics_.first_snapshot()) r.active_s = std::chrono::duration<double>(now - *first).count();
  r.latency_ms = metrics_.latency_ms();
  r.interarrival_ms = metrics_.interarrival_ms();
  r.staleness_ms = metrics_.staleness_ms();
  r.first_pose = first_pose_;
  r.last_pose = world_.own_pose();
  if (r.first_pose && r.last_pose) r.moved_m = std::hypot(r.last_pose->x - r.first_pose->x, r.last_pose->y - r.first_pose->y);
  r.world_objects = world_.object_count();
  r.rejoins = rejoins_;
  return r;
}

Samples Bot::take_window_latency() {
  std::lock_guard lock(mutex_);
  return metrics_.take_window_latency();
}
std::optional<ObjectState> Bot::own_pose() const {
  std::lock_guard lock(mutex_);
  return world_.own_pose();
}
std::optional<ObjectState> Bot::object(std::uint32_t id) const {
  std::lock_guard lock(mutex_);
  return world_.object(id);
}
std::size_t Bot::world_objects() const {
  std::lock_guard lock(mutex_);
  return world_.object_count();
}
std::uint64_t Bot::snapshots_received() const {
  std::lock_guard lock(mutex_);
  return metrics_.snapshots().samples;
}
std::uint64_t Bot::bytes_received() const {
  std::lock_guard lock(mutex_);
  return metrics_.snapshots().bytes;
}
std::uint64_t Bot::missed_ticks() const {
  std::lock_guard lock(mutex_);
  return metrics_.snapshots().missed_ticks;
}
std::uint64_t Bot::commands_sent() const {
  std::lock_guard lock(mutex_);
  return metrics_.commands().sent;
}

}  // namespace throng::client_sim
