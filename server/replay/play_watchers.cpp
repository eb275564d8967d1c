// Watchers of a played log: spectators with their own snapshot stream (see play_watchers.h).
#include "play_watchers.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "throng/core/object_id.h"
#include "throng/world/world.h"

namespace throng::replay {

namespace {

// A body moving slower than this keeps its previous facing (the AI's rule for NPCs: standing
// bodies do not spin to yaw 0).
constexpr double kStillSpeed2 = 0.05 * 0.05;
constexpr std::size_t kMaxNameBytes = 64;  // as the live match checks
constexpr std::size_t kNone = static_cast<std::size_t>(-1);

std::uint8_t faction_of(const protocol::MatchInfo& info, std::uint32_t entity) {
  const auto& r = info.roster;
  for (std::size_t i = 0; i < r.id.size() && i < r.faction.size(); ++i)
    if (r.id[i] == entity) return r.faction[i];
  return 0;
}

protocol::JoinReply refusal(std::uint64_t nonce, protocol::JoinResult result, std::string reason, std::uint64_t tick) {
  protocol::JoinReply r;
  r.client_nonce = nonce;
  r.result = result;
  r.reason = std::move(reason);
  r.tick = tick;
  return r;
}

}  // namespace

Watchers::Watchers(const match::InterestConfig& interest, WatcherOptions options) : builder_(interest), options_(options) {}

// Round-robin over the logged clients connected now (by id, so the choice is reproducible);
// with none, the movable nearest the centre of all movables: the middle of the battle.
std::uint32_t Watchers::pick_entity(const match::Match& match) {
  auto clients = match.clients();
  if (!clients.empty()) {
    std::sort(clients.begin(), clients.end(), [](const auto& a, const auto& b) { return a.client_id < b.client_id; });
    return clients[round_robin_++ % clients.size()].entity;
  }
  const World& w = match.world();
  const auto xs = w.pos_x(), ys = w.pos_y();
  if (xs.empty()) return 0;
  double cx = 0, cy = 0;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    cx += xs[i];
    cy += ys[i];
  }
  cx /= static_cast<double>(xs.size());
  cy /= static_cast<double>(xs.size());
  std::uint32_t best = 0;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const double d2 = (xs[i] - cx) * (xs[i] - cx) + (ys[i] - cy) * (ys[i] - cy);
    const std::uint32_t id = w.id_at(i).value;
    if (d2 < best_d2 || (d2 == best_d2 && id < best)) {
      best_d2 = d2;
      best = id;
    }
  }
  return best;
}

void Watchers::handle_requests(const std::vector<protocol::JoinRequest>& requests, const match::Match& match, bool ending,
                               Clock::time_point now, WatcherChanges& out) {
  const std::uint64_t tick = match.tick_index();
  for (const auto& req : requests) {
    if (req.leave) {
      const auto it = watchers_.find(req.client_id);
      if (it != watchers_.end() && it->second.owner != req.sender) continue;  // another participant's watcher
      if (it == watchers_.end()) {
        out.replies.push_back(refusal(req.client_nonce, protocol::JoinResult::bad_request,
                                      fmt::format("client {} is not a watcher of this replay", req.client_id), tick));
        continue;
      }
      protocol::JoinReply r = refusal(req.client_nonce, protocol::JoinResult::left, "", tick);
      r.client_id = req.client_id;
      r.entity = it->second.entity;
      out.replies.push_back(std::move(r));
      out.channels.push_back({req.client_id, ""});
      builder_.remove_client(req.client_id);
      watchers_.erase(it);
      ++totals_.left;
      continue;
    }
    // A repeated request (the client retrying) gets the same answer, not a second seat.
    const auto same = std::find_if(watchers_.begin(), watchers_.end(), [&](const auto& w) {
      return w.second.nonce == req.client_nonce && w.second.owner == req.sender;
    });
    const protocol::JoinResult why = req.protocol_version != protocol::kProtocolVersion ? protocol::JoinResult::bad_version
                                     : req.client_nonce == 0 || req.name.size() > kMaxNameBytes ? protocol::JoinResult::bad_request
                                     : ending                                                ? protocol::JoinResult::shutting_down
                                     : same == watchers_.end() && watchers_.size() >= options_.max_watchers
                                         ? protocol::JoinResult::match_full
                                         : protocol::JoinResult::accepted;
    if (why != protocol::JoinResult::accepted) {
      const char* reason = why == protocol::JoinResult::bad_version     ? "protocol version differs from this replay's"
                           : why == protocol::JoinResult::bad_request   ? "empty nonce or name over 64 bytes"
                           : why == protocol::JoinResult::shutting_down ? "the replay is ending"
                                                                        : "too many watchers (--max-watchers)";
      out.replies.push_back(refusal(req.client_nonce, why, reason, tick));
      ++totals_.refused;
      continue;
    }
    std::uint32_t id = 0;
    if (same != watchers_.end()) {
      id = same->first;
    } else {
      id = next_id_++;
      Watcher w;
      w.nonce = req.client_nonce;
      w.name = req.name;
      w.entity = pick_entity(match);
      w.last_heard = now;
      w.owner = req.sender;
      // Under DDS Security a watcher may read only partitions named after its certificate, as at
      // the live server (server/match/src/client_registry.h).
      w.partition = req.identity.empty() ? fmt::format("w{}", id - kWatcherIdBase)
                                         : fmt::format("{}{}_{}", protocol::kIdentityPartitionPrefix, req.identity, id);
      builder_.add_client(id);
      out.channels.push_back({id, w.partition});
      watchers_.emplace(id, std::move(w));
      ++totals_.joined;
    }
    const Watcher& w = watchers_.at(id);
    protocol::JoinReply r;
    r.client_nonce = req.client_nonce;
    r.result = protocol::JoinResult::accepted;
    r.reason = fmt::format("spectator of a replay: following entity {}; commands are ignored", w.entity);
    r.client_id = id;
    r.entity = w.entity;
    r.snapshot_partition = w.partition;
    r.tick = tick;
    r.faction = faction_of(match.match_info(), w.entity);
    out.replies.push_back(std::move(r));
  }
}

void Watchers::note_command(std::uint32_t client_id, Clock::time_point now) {
  ++totals_.commands_ignored;
  const auto it = watchers_.find(client_id);
  if (it != watchers_.end()) it->second.last_heard = now;
}

void Watchers::expire(Clock::time_point now, WatcherChanges& out) {
  if (options_.timeout == Clock::duration::zero()) return;
  for (auto it = watchers_.begin(); it != watchers_.end();) {
    if (now - it->second.last_heard > options_.timeout) {
      out.channels.push_back({it->first, ""});
      builder_.remove_client(it->first);
      it = watchers_.erase(it);
      ++totals_.timed_out;
    } else {
      ++it;
    }
  }
}

// The bodies of this tick for the builder. Facing: the Match's own facings are private, so a
// body's yaw here is the direction of its velocity over the last tick, kept while it stands.
// Positions are exact; yaw is an approximation for players' entities (whose facing comes from
// their commands) and close to the AI's rule for NPCs.
void Watchers::index_bodies(const match::Match& match) {
  const World& w = match.world();
  const std::size_t n = w.pos_x().size();
  ids_.resize(n);
  yaw_dense_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const ObjectId id = w.id_at(i);
    const std::uint32_t index = id.index();
    if (index >= yaw_by_index_.size()) {
      yaw_by_index_.resize(index + 1, 0.0f);
      dense_by_index_.resize(index + 1, 0);
    }
    const Vec3 v = w.velocity(id);
    if (v.x * v.x + v.y * v.y > kStillSpeed2) yaw_by_index_[index] = static_cast<float>(std::atan2(v.y, v.x));
    ids_[i] = id.value;
    yaw_dense_[i] = yaw_by_index_[index];
    dense_by_index_[index] = static_cast<std::uint32_t>(i);
  }
}

void Watchers::build_snapshots(const match::Match& match, std::vector<protocol::Snapshot>& out) {
  out.resize(watchers_.size());
  if (watchers_.empty()) return;
  index_bodies(match);
  const World& w = match.world();
  const auto xs = w.pos_x(), ys = w.pos_y(), zs = w.pos_z();
  const std::uint64_t tick = match.tick_index();
  builder_.index(match::BodyView{ids_, xs, ys, zs, yaw_dense_}, tick);
  std::size_t k = 0;
  for (auto& [id, watcher] : watchers_) {
    // The followed entity's dense slot (re-picked should it ever leave the world).
    auto dense_of = [&](std::uint32_t e) -> std::size_t {
      const std::uint32_t index = ObjectId{e}.index();
      if (e == 0 || index >= dense_by_index_.size()) return kNone;
      const std::uint32_t d = dense_by_index_[index];
      return d < ids_.size() && ids_[d] == e ? d : kNone;
    };
    std::size_t d = dense_of(watcher.entity);
    if (d == kNone) {
      watcher.entity = pick_entity(match);
      d = dense_of(watcher.entity);
    }
    protocol::Snapshot& s = out[k++];
    s.client_id = id;
    s.tick = tick;
    s.last_applied_sequence = 0;  // nothing a watcher sends is applied
    s.last_applied_tick = 0;
    if (d == kNone) {  // an empty world: nothing to follow
      s.entity = 0;
      s.entity_x = s.entity_y = s.entity_z = s.entity_yaw = 0;
    } else {
      s.entity = watcher.entity;
      s.entity_x = static_cast<float>(xs[d]);
      s.entity_y = static_cast<float>(ys[d]);
      s.entity_z = static_cast<float>(zs[d]);
      s.entity_yaw = yaw_dense_[d];
    }
    const double cam_x = d == kNone ? 0.0 : xs[d], cam_y = d == kNone ? 0.0 : ys[d];
    builder_.build(id, cam_x, cam_y, s, scratch_);
  }
}

}  // namespace throng::replay
