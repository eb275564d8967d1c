// Commands: validated in the drained order (entity, sequence, client id), each either applied or
// rejected with the first failing check of: unknown_client, foreign_participant (sent by another
// participant than the one that joined the client), not_your_entity, non_finite, move /
// facing / camera range, bad_actions, stale/duplicate sequence, rate_limited. A rejected command
// changes nothing at all (no state, no sequence, no activity time).
//
// Applied commands, in sequence order, so the newest of a tick wins: desired velocity = move *
// player speed (x1.5 sprinting), kept until the next command (thin client); facing -> the entity's
// yaw; camera -> interest management and the engine's camera-distance input; brace held -> the
// entity weighs kBraceWeightFactor times its weight until released.
#include <algorithm>

#include "command_validation.h"
#include "match_impl.h"
#include "throng/params/object_params.h"
#include "throng/world/world.h"

namespace throng::match {

std::optional<RejectReason> Match::Impl::check_command(const protocol::Command& cmd, std::uint64_t tick) {
  const ClientRecord* c = clients.find_connected(cmd.client_id);
  if (c == nullptr) return RejectReason::unknown_client;
  if (cmd.sender != c->owner) return RejectReason::foreign_participant;
  if (cmd.entity != c->entity.value) return RejectReason::not_your_entity;
  if (auto bad = check_command_fields(cmd, config)) return bad;
  if (cmd.sequence <= c->last_applied_sequence) {
    return cmd.sequence == c->last_applied_sequence && cmd.sequence != 0 ? RejectReason::duplicate_sequence
                                                                         : RejectReason::stale_sequence;
  }
  if (c->rate_tick == tick && c->accepted_in_tick >= config.max_commands_per_tick) return RejectReason::rate_limited;
  return std::nullopt;
}

double Match::Impl::braced_weight(double base_kg) const {
  const params::ParamRange range = params::param_range(params::Param::weight_kg);
  return std::min(base_kg * kBraceWeightFactor, range.max);
}

void Match::Impl::set_brace(ClientRecord& c, bool bracing) {
  if (c.bracing == bracing) return;
  world().set_param(c.entity, params::Param::weight_kg, bracing ? braced_weight(c.base_weight_kg) : c.base_weight_kg);
  c.bracing = bracing;
}

void Match::Impl::apply_commands(std::uint64_t tick) {
  for (const protocol::Command& cmd : inputs.commands) {
    if (const std::optional<RejectReason> why = check_command(cmd, tick)) {
      ++rejected[static_cast<std::size_t>(*why)];
      ++report.commands_rejected;
      if (ClientRecord* sender = clients.find(cmd.client_id)) ++sender->commands_rejected;
      continue;
    }
    ClientRecord& c = *clients.find_connected(cmd.client_id);
    if (c.rate_tick != tick) {
      c.rate_tick = tick;
      c.accepted_in_tick = 0;
    }
    ++c.accepted_in_tick;
    const MoveVector move = clamped_move(cmd);
    const double speed =
        config.player_speed_mps * ((cmd.actions & protocol::kActionSprint) != 0u ? kSprintFactor : 1.0);
    world().set_desired_velocity(c.entity, Vec3{move.x * speed, move.y * speed, 0.0});
    yaw[dense_of(c.entity)] = cmd.facing_rad;
    c.camera = Vec3{cmd.camera_x, cmd.camera_y, cmd.camera_z};
    c.has_camera = true;
    set_brace(c, (cmd.actions & protocol::kActionBrace) != 0u);
    note_contacts_request(c, (cmd.actions & protocol::kActionContacts) != 0u);  // never touches the world
    c.last_applied_sequence = cmd.sequence;
    c.last_applied_tick = tick;
    c.last_activity_tick = tick;
    ++accepted_total;
    ++c.commands_accepted;
    ++report.commands_accepted;
  }
}

Vec3 Match::Impl::camera_of(const ClientRecord& c) const {
  if (c.has_camera) return c.camera;
  const World& w = world();
  const std::uint32_t d = dense_of(c.entity);
  return Vec3{w.pos_x()[d], w.pos_y()[d], w.pos_z()[d]};
}

void Match::Impl::feed_cameras() {
  cameras.clear();
  for (std::uint32_t id : clients.connected_ids()) cameras.push_back(camera_of(*clients.find(id)));
  world().set_cameras(cameras);
}

}  // namespace throng::match
