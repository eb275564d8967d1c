// Joins, leaves and timeouts: who controls which entity.
//
// Join checks, in order: protocol version (bad_version), nonce 0 (bad_request), then leaves are
// handled (below), name longer than 64 bytes (bad_request), a nonce that is already connected gets
// its original reply again (reliable transports may redeliver), shutting down, match full, no
// free character (match_full). An accepted client takes over an NPC: factions alternate by client
// id over the factions present (1, 2, 1, 2, ...; a faction without a free NPC passes to the next),
// and the chosen body is the free one closest to its faction's centroid (ties: lower id). Its
// character_type becomes player and its importance the player importance; the NPC values are kept
// and restored when the client leaves or times out.
//
// A leave must name a client id together with the nonce that client joined with; a repeated leave
// of a client that already left is answered `left` again.
//
// Binding: a client belongs to the participant that sent its join (JoinRequest::sender). A leave,
// or a repeated join, of a client from another participant is refused as foreign_participant and
// answered with nothing: the reply topic is keyed by nonce, so any reply would replace the owner's
// own reply for late joiners.
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "match_impl.h"
#include "throng/params/categories.h"
#include "throng/params/object_params.h"
#include "throng/world/world.h"

namespace throng::match {
namespace {

protocol::JoinReply refusal(const protocol::JoinRequest& r, protocol::JoinResult result, std::string reason,
                            std::uint64_t tick) {
  protocol::JoinReply reply;
  reply.client_nonce = r.client_nonce;
  reply.result = result;
  reply.reason = std::move(reason);
  reply.tick = tick;
  return reply;
}

}  // namespace

protocol::JoinReply Match::Impl::accepted_reply(const ClientRecord& c, std::uint64_t tick) const {
  protocol::JoinReply reply;
  reply.client_nonce = c.nonce;
  reply.result = protocol::JoinResult::accepted;
  reply.client_id = c.id;
  reply.entity = c.entity.value;
  reply.snapshot_partition = c.partition;
  reply.tick = tick;
  reply.faction = c.faction;
  return reply;
}

void Match::Impl::apply_joins(std::uint64_t tick, Outbox& out) {
  for (const protocol::JoinRequest& r : inputs.joins) {
    if (r.protocol_version != protocol::kProtocolVersion) {
      out.join_replies.push_back(refusal(r, protocol::JoinResult::bad_version,
                                         fmt::format("client protocol version {} does not match the server's version {}",
                                                     r.protocol_version, protocol::kProtocolVersion),
                                         tick));
      ++report.joins_refused;
    } else if (r.client_nonce == 0) {
      out.join_replies.push_back(
          refusal(r, protocol::JoinResult::bad_request, "client_nonce must not be 0", tick));
      ++report.joins_refused;
    } else if (r.leave) {
      handle_leave(r, tick, out);
    } else {
      handle_join(r, tick, out);
    }
  }
}

void Match::Impl::handle_join(const protocol::JoinRequest& r, std::uint64_t tick, Outbox& out) {
  using protocol::JoinResult;
  if (r.name.size() > kMaxNameBytes) {
    out.join_replies.push_back(refusal(
        r, JoinResult::bad_request, fmt::format("name is {} bytes long (at most {})", r.name.size(), kMaxNameBytes),
        tick));
    ++report.joins_refused;
    return;
  }
  if (const ClientRecord* existing = clients.find_connected_nonce(r.client_nonce)) {
    if (existing->owner != r.sender) {
      ++report.joins_foreign;
      return;
    }
    protocol::JoinReply again = accepted_reply(*existing, existing->joined_tick);
    out.join_replies.push_back(std::move(again));
    return;
  }
  if (shutting_down) {
    out.join_replies.push_back(refusal(r, JoinResult::shutting_down, "the match is shutting down", tick));
    ++report.joins_refused;
    return;
  }
  if (clients.connected_count() >= config.max_clients) {
    out.join_replies.push_back(
        refusal(r, JoinResult::match_full, fmt::format("the match is full ({} clients)", config.max_clients), tick));
    ++report.joins_refused;
    return;
  }
  const std::optional<std::uint32_t> dense = choose_entity(clients.next_id());
  if (!dense) {
    out.join_replies.push_back(refusal(r, JoinResult::match_full, "no free character to control", tick));
    ++report.joins_refused;
    return;
  }
  ClientRecord& c = clients.add(r.client_nonce, r.name, r.sender, r.identity);
  take_over(c, *dense, tick);
  out.client_events.push_back(ClientEvent{ClientEvent::Kind::joined, c.id, c.entity.value, c.partition, c.name});
  out.join_replies.push_back(accepted_reply(c, tick));
  ++report.joins_accepted;
}

void Match::Impl::handle_leave(const protocol::JoinRequest& r, std::uint64_t tick, Outbox& out) {
  // Whatever id it names, a leave carrying a connected client's nonce from another participant gets
  // no reply: the reply topic is keyed by nonce, and any reply would replace that client's own.
  const ClientRecord* nonce_owner = clients.find_connected_nonce(r.client_nonce);
  if (nonce_owner != nullptr && nonce_owner->owner != r.sender) {
    ++report.joins_foreign;
    return;
  }
  ClientRecord* c = clients.find_connected(r.client_id);
  if (c == nullptr && nonce_owner == nullptr && clients.was_given_out(r.client_id)) {
    // Left or timed out before (a repeated leave, or a leave after the timeout): its record is
    // gone, so there is no owner to check, but the nonce is no connected client's. The reply
    // changes nothing and says what the roster says: the id is not connected.
    protocol::JoinReply reply = refusal(r, protocol::JoinResult::left,
                                        fmt::format("client {} is not connected (it left or timed out)", r.client_id), tick);
    reply.client_id = r.client_id;
    out.join_replies.push_back(std::move(reply));
    return;
  }
  if (c == nullptr || c->nonce != r.client_nonce) {
    out.join_replies.push_back(refusal(r, protocol::JoinResult::bad_request,
                                       fmt::format("leave for unknown client {}", r.client_id), tick));
    ++report.joins_refused;
    return;
  }
  if (c->owner != r.sender) {
    ++report.joins_foreign;
    return;
  }
  protocol::JoinReply reply = accepted_reply(*c, tick);
  reply.result = protocol::JoinResult::left;
  reply.reason = "left";
  release(*c);
  out.client_events.push_back(ClientEvent{ClientEvent::Kind::left, c->id, c->entity.value, c->partition, c->name,
                                                c->commands_accepted, c->commands_rejected});
  ++report.leaves;
  out.join_replies.push_back(std::move(reply));
}

void Match::Impl::apply_timeouts(std::uint64_t tick, Outbox& out) {
  std::size_t i = 0;
  while (i < clients.connected_ids().size()) {
    ClientRecord& c = *clients.find(clients.connected_ids()[i]);
    if (tick - c.last_activity_tick < timeout_ticks) {
      ++i;
      continue;
    }
    release(c);  // removes it from connected_ids: i now names the next client
    out.client_events.push_back(ClientEvent{ClientEvent::Kind::timed_out, c.id, c.entity.value, c.partition, c.name,
                                                  c.commands_accepted, c.commands_rejected});
    // The reply topic is keyed by nonce and kept for late joiners: tell them the entity is free.
    protocol::JoinReply reply = accepted_reply(c, tick);
    reply.result = protocol::JoinResult::left;
    reply.reason = fmt::format("timed out: no command for {} ticks", timeout_ticks);
    out.join_replies.push_back(std::move(reply));
    ++report.timeouts;
  }
}

std::optional<std::uint32_t> Match::Impl::choose_entity(std::uint32_t client_id) const {
  const World& w = world();
  const std::size_t n = w.body_count();
  std::array<bool, 256> present{};
  for (std::size_t d = 0; d < n; ++d) present[w.params(w.id_at(d)).faction] = true;
  std::vector<std::uint8_t> factions;
  for (std::size_t f = 1; f < present.size(); ++f) {
    if (present[f]) factions.push_back(static_cast<std::uint8_t>(f));
  }
  if (factions.empty() && present[0]) factions.push_back(0);
  if (factions.empty()) return std::nullopt;
  const auto xs = w.pos_x();
  const auto ys = w.pos_y();
  const std::size_t first = (client_id - 1u) % factions.size();
  for (std::size_t k = 0; k < factions.size(); ++k) {
    const std::uint8_t f = factions[(first + k) % factions.size()];
    double sx = 0.0, sy = 0.0;
    std::size_t members = 0;
    for (std::size_t d = 0; d < n; ++d) {
      if (w.params(w.id_at(d)).faction != f) continue;
      sx += xs[d];
      sy += ys[d];
      ++members;
    }
    if (members == 0) continue;
    const double cx = sx / static_cast<double>(members);
    const double cy = sy / static_cast<double>(members);
    std::optional<std::uint32_t> best;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (std::size_t d = 0; d < n; ++d) {
      if (controller[d] != 0 || w.params(w.id_at(d)).faction != f) continue;
      const double dx = xs[d] - cx;
      const double dy = ys[d] - cy;
      const double d2 = dx * dx + dy * dy;
      if (d2 < best_d2 || (d2 == best_d2 && best && id_values[d] < id_values[*best])) {
        best_d2 = d2;
        best = static_cast<std::uint32_t>(d);
      }
    }
    if (best) return best;
  }
  return std::nullopt;
}

void Match::Impl::take_over(ClientRecord& c, std::uint32_t dense, std::uint64_t tick) {
  World& w = world();
  const ObjectId id = w.id_at(dense);
  const params::ObjectParams& p = w.params(id);
  c.entity = id;
  c.faction = p.faction;
  c.joined_tick = tick;
  c.last_activity_tick = tick;
  c.npc_character_type = p.get(params::Param::character_type);
  c.npc_importance = p.importance;
  c.base_weight_kg = p.weight_kg;
  c.bracing = false;
  w.set_param(id, params::Param::character_type, static_cast<double>(params::CharacterType::player));
  w.set_param(id, params::Param::importance, player_importance);
  w.set_desired_velocity(id, Vec3{});  // stands until the first command
  controller[dense] = c.id;
  snapshots.add_client(c.id);
}

void Match::Impl::release(ClientRecord& c) {
  World& w = world();
  w.set_desired_velocity(c.entity, Vec3{});
  w.set_param(c.entity, params::Param::character_type, c.npc_character_type);
  w.set_param(c.entity, params::Param::importance, c.npc_importance);
  if (c.bracing) w.set_param(c.entity, params::Param::weight_kg, c.base_weight_kg);
  c.bracing = false;
  controller[dense_of(c.entity)] = 0;
  snapshots.remove_client(c.id);
  clients.disconnect(c.id);
}

}  // namespace throng::match
