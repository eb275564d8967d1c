#include "throng/client_sim/client_world.h"

#include <algorithm>
#include <cmath>

namespace throng::client_sim {

namespace {
double wrap_angle(double a) {
  // to (-pi, pi]
  a = std::remainder(a, 2.0 * protocol::kPi);
  return a <= -protocol::kPi ? a + 2.0 * protocol::kPi : a;
}
}  // namespace

ClientWorld::ClientWorld(const Options& options) : options_(options) { update_expiry(); }

void ClientWorld::set_match(std::shared_ptr<const MatchView> match) {
  match_ = std::move(match);
  update_expiry();
}

void ClientWorld::update_expiry() {
  expiry_ticks_ = static_cast<std::uint64_t>(std::llround(std::max(0.0, options_.expiry_s) * tick_hz()));
}

double ClientWorld::render_tick() const {
  if (!newest_tick_) return 0.0;
  return std::max(0.0, static_cast<double>(*newest_tick_) - options_.interp_delay_ticks);
}

bool ClientWorld::expired(const Track& t) const {
  if (t.n == 0 || !newest_tick_) return true;
  return *newest_tick_ - t.s[t.n - 1].tick > expiry_ticks_;
}

ClientWorld::ApplyResult ClientWorld::apply(const protocol::Snapshot& snap) {
  if (newest_tick_ && snap.tick <= *newest_tick_) {
    ++stale_;
    return ApplyResult::stale;
  }
  scratch_.clear();
  try {
    protocol::decode_poses(snap, scratch_);
  } catch (const protocol::DecodeError& e) {
    ++malformed_;
    last_error_ = e.what();
    return ApplyResult::malformed;
  }
  const bool own = snap.entity != 0;
  if (own && !(std::isfinite(snap.entity_x) && std::isfinite(snap.entity_y) && std::isfinite(snap.entity_z) &&
               std::isfinite(snap.entity_yaw))) {
    ++malformed_;
    last_error_ = "snapshot: non-finite own entity pose";
    return ApplyResult::malformed;
  }

  newest_tick_ = snap.tick;
  for (std::uint32_t id : snap.removed) tracks_.erase(id);
  for (const auto& p : scratch_) add_sample(p.id, Sample{snap.tick, p.x, p.y, p.z, p.yaw});
  own_entity_ = snap.entity;
  if (own) {
    const Sample s{snap.tick, snap.entity_x, snap.entity_y, snap.entity_z, wrap_angle(snap.entity_yaw)};
    add_sample(snap.entity, s);
    own_pose_ = ObjectState{snap.entity, s.x, s.y, s.z, s.yaw};
  } else {
    own_pose_.reset();
  }
  ++applied_;
  // Sweep expired objects once a second of server time (object_at checks expiry too, so the
  // sweep only bounds memory).
  if (snap.tick - last_sweep_tick_ >= std::max<std::uint64_t>(1, tick_hz())) sweep();
  return ApplyResult::applied;
}

void ClientWorld::add_sample(std::uint32_t id, const Sample& sample) {
  Track& t = tracks_[id];
  if (t.n > 0 && t.s[t.n - 1].tick == sample.tick) {
    t.s[t.n - 1] = sample;  // same tick (own pose after its quantized copy): the later one wins
    return;
  }
  if (t.n == kSamples) {
    std::move(t.s.begin() + 1, t.s.end(), t.s.begin());
    t.n = kSamples - 1;
  }
  t.s[t.n++] = sample;
}

void ClientWorld::sweep() {
  last_sweep_tick_ = newest_tick_.value_or(0);
  std::erase_if(tracks_, [this](const auto& kv) { return expired(kv.second); });
}

ObjectState ClientWorld::sample_track(std::uint32_t id, const Track& t, double tick) {
  const Sample* a = &t.s[0];
  const Sample* b = a;
  if (tick <= static_cast<double>(t.s[0].tick)) {
    b = a;
  } else if (tick >= static_cast<double>(t.s[t.n - 1].tick)) {
    a = b = &t.s[t.n - 1];
  } else {
    for (std::size_t i = 0; i + 1 < t.n; ++i) {
      if (tick >= static_cast<double>(t.s[i].tick) && tick <= static_cast<double>(t.s[i + 1].tick)) {
        a = &t.s[i];
        b = &t.s[i + 1];
        break;
      }
    }
  }
  if (a == b || b->tick == a->tick) return ObjectState{id, a->x, a->y, a->z, a->yaw};
  const double f = (tick - static_cast<double>(a->tick)) / static_cast<double>(b->tick - a->tick);
  const double dyaw = wrap_angle(b->yaw - a->yaw);
  return ObjectState{id, a->x + (b->x - a->x) * f, a->y + (b->y - a->y) * f, a->z + (b->z - a->z) * f,
                     wrap_angle(a->yaw + dyaw * f)};
}

std::optional<ObjectState> ClientWorld::object_at(std::uint32_t id, double tick) const {
  auto it = tracks_.find(id);
  if (it == tracks_.end() || expired(it->second)) return std::nullopt;
  return sample_track(id, it->second, tick);
}

void ClientWorld::for_each(const std::function<void(const ObjectState&)>& fn) const {
  const double t = render_tick();
  for (const auto& [id, track] : tracks_)
    if (!expired(track)) fn(sample_track(id, track, t));
}

std::size_t ClientWorld::object_count() const {
  std::size_t n = 0;
  for (const auto& kv : tracks_) n += expired(kv.second) ? 0 : 1;
  return n;
}

}  // namespace throng::client_sim
