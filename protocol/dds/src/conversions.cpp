#include "conversions.h"

#include <utility>

namespace throng::protocol::dds_detail {

namespace {
template <class Enum>
std::uint8_t octet(Enum e) { return static_cast<std::uint8_t>(e); }
}  // namespace

// --- to the wire ------------------------------------------------------------------------------

v1::JoinRequest to_idl(const JoinRequest& m) {
  v1::JoinRequest s;
  s.client_nonce(m.client_nonce);
  s.protocol_version(m.protocol_version);
  s.name(m.name);
  s.leave(m.leave);
  s.client_id(m.client_id);
  return s;
}

v1::JoinReply to_idl(const JoinReply& m) {
  v1::JoinReply s;
  s.client_nonce(m.client_nonce);
  s.result(octet(m.result));
  s.reason(m.reason);
  s.client_id(m.client_id);
  s.entity(m.entity);
  s.snapshot_partition(m.snapshot_partition);
  s.tick(m.tick);
  s.faction(m.faction);
  return s;
}

v1::Command to_idl(const Command& m) {
  v1::Command s;
  s.client_id(m.client_id);
  s.entity(m.entity);
  s.sequence(m.sequence);
  s.last_seen_tick(m.last_seen_tick);
  s.move_x(m.move_x);
  s.move_y(m.move_y);
  s.facing_rad(m.facing_rad);
  s.actions(m.actions);
  s.camera_x(m.camera_x);
  s.camera_y(m.camera_y);
  s.camera_z(m.camera_z);
  return s;
}

v1::Snapshot to_idl(const Snapshot& m) {
  v1::Snapshot s;
  s.client_id(m.client_id);
  s.tick(m.tick);
  s.last_applied_sequence(m.last_applied_sequence);
  s.last_applied_tick(m.last_applied_tick);
  s.entity(m.entity);
  s.entity_x(m.entity_x);
  s.entity_y(m.entity_y);
  s.entity_z(m.entity_z);
  s.entity_yaw(m.entity_yaw);
  s.origin_x_mm(m.origin_x_mm);
  s.origin_y_mm(m.origin_y_mm);
  s.unit_mm(m.unit_mm);
  s.objects_in_view(m.objects_in_view);
  s.id_codes(m.id_codes);
  s.x(m.x);
  s.y(m.y);
  s.z(m.z);
  s.yaw(m.yaw);
  s.removed(m.removed);
  return s;
}

namespace {
v1::SceneryShape to_idl(const SceneryShape& m) {
  v1::SceneryShape s;
  s.id(m.id);
  s.kind(octet(m.kind));
  s.archetype(m.archetype);
  s.softness(m.softness);
  s.cx(m.cx);
  s.cy(m.cy);
  s.cz(m.cz);
  s.hx(m.hx);
  s.hy(m.hy);
  s.hz(m.hz);
  s.yaw_rad(m.yaw_rad);
  s.radius(m.radius);
  s.half_height(m.half_height);
  s.vertices(m.vertices);
  s.triangles(m.triangles);
  return s;
}

v1::RosterArrays to_idl(const Roster& m) {
  v1::RosterArrays s;
  s.id(m.id);
  s.radius_mm(m.radius_mm);
  s.half_height_mm(m.half_height_mm);
  s.faction(m.faction);
  s.character_type(m.character_type);
  s.archetype(m.archetype);
  return s;
}
}  // namespace

v1::MatchInfo to_idl(const MatchInfo& m) {
  v1::MatchInfo s;
  s.protocol_version(m.protocol_version);
  s.match_id(m.match_id);
  s.scene_name(m.scene_name);
  s.tick_hz(m.tick_hz);
  s.start_tick(m.start_tick);
  s.param_table_hash(m.param_table_hash);
  s.push_policy_hash(m.push_policy_hash);
  s.param_version(m.param_version);
  s.max_clients(m.max_clients);
  s.interest_radius_m(m.interest_radius_m);
  s.world_min_x(m.world_min_x);
  s.world_min_y(m.world_min_y);
  s.world_max_x(m.world_max_x);
  s.world_max_y(m.world_max_y);
  s.state(octet(m.state));
  s.archetypes(m.archetypes);
  s.scenery().reserve(m.scenery.size());
  for (const SceneryShape& shape : m.scenery) s.scenery().push_back(to_idl(shape));
  s.roster(to_idl(m.roster));
  return s;
}

v1::ParamUpdate to_idl(const ParamUpdate& m) {
  v1::ParamUpdate s;
  s.request_id(m.request_id);
  s.entity(m.entity);
  s.param(m.param);
  s.value(m.value);
  s.policy_json(m.policy_json);
  return s;
}

v1::ParamReply to_idl(const ParamReply& m) {
  v1::ParamReply s;
  s.request_id(m.request_id);
  s.ok(m.ok);
  s.error(m.error);
  s.param_version(m.param_version);
  s.tick(m.tick);
  return s;
}

v1::ServerStats to_idl(const ServerStats& m) {
  v1::ServerStats s;
  s.tick(m.tick);
  s.tick_hz(m.tick_hz);
  s.clients(m.clients);
  s.bodies(m.bodies);
  s.tick_ms_p50(m.tick_ms_p50);
  s.tick_ms_p99(m.tick_ms_p99);
  s.tick_ms_max(m.tick_ms_max);
  s.overruns(m.overruns);
  s.commands_accepted(m.commands_accepted);
  s.commands_rejected(m.commands_rejected);
  s.snapshot_bytes(m.snapshot_bytes);
  s.snapshot_samples(m.snapshot_samples);
  s.push_events(m.push_events);
  s.state_hash(m.state_hash);
  s.state(octet(m.state));
  return s;
}

v1::ContactPairs to_idl(const ContactPairs& m) {
  v1::ContactPairs s;
  s.client_id(m.client_id);
  s.tick(m.tick);
  s.pairs_near(m.pairs_near);
  s.camera_x(m.camera_x);
  s.camera_y(m.camera_y);
  s.radius_m(m.radius_m);
  s.a(m.a);
  s.b(m.b);
  s.share_a(m.share_a);
  s.depth(m.depth);
  s.push(m.push);
  return s;
}

// --- from the wire ----------------------------------------------------------------------------

JoinRequest from_idl(v1::JoinRequest&& s) {
  JoinRequest m;
  m.client_nonce = s.client_nonce();
  m.protocol_version = s.protocol_version();
  m.name = std::move(s.name());
  m.leave = s.leave();
  m.client_id = s.client_id();
  return m;
}

JoinReply from_idl(v1::JoinReply&& s) {
  JoinReply m;
  m.client_nonce = s.client_nonce();
  m.result = static_cast<JoinResult>(s.result());
  m.reason = std::move(s.reason());
  m.client_id = s.client_id();
  m.entity = s.entity();
  m.snapshot_partition = std::move(s.snapshot_partition());
  m.tick = s.tick();
  m.faction = s.faction();
  return m;
}

Command from_idl(v1::Command&& s) {
  Command m;
  m.client_id = s.client_id();
  m.entity = s.entity();
  m.sequence = s.sequence();
  m.last_seen_tick = s.last_seen_tick();
  m.move_x = s.move_x();
  m.move_y = s.move_y();
  m.facing_rad = s.facing_rad();
  m.actions = s.actions();
  m.camera_x = s.camera_x();
  m.camera_y = s.camera_y();
  m.camera_z = s.camera_z();
  return m;
}

Snapshot from_idl(v1::Snapshot&& s) {
  Snapshot m;
  m.client_id = s.client_id();
  m.tick = s.tick();
  m.last_applied_sequence = s.last_applied_sequence();
  m.last_applied_tick = s.last_applied_tick();
  m.entity = s.entity();
  m.entity_x = s.entity_x();
  m.entity_y = s.entity_y();
  m.entity_z = s.entity_z();
  m.entity_yaw = s.entity_yaw();
  m.origin_x_mm = s.origin_x_mm();
  m.origin_y_mm = s.origin_y_mm();
  m.unit_mm = s.unit_mm();
  m.objects_in_view = s.objects_in_view();
  m.id_codes = std::move(s.id_codes());
  m.x = std::move(s.x());
  m.y = std::move(s.y());
  m.z = std::move(s.z());
  m.yaw = std::move(s.yaw());
  m.removed = std::move(s.removed());
  return m;
}

namespace {
SceneryShape from_idl(v1::SceneryShape&& s) {
  SceneryShape m;
  m.id = s.id();
  m.kind = static_cast<ShapeKind>(s.kind());
  m.archetype = std::move(s.archetype());
  m.softness = s.softness();
  m.cx = s.cx();
  m.cy = s.cy();
  m.cz = s.cz();
  m.hx = s.hx();
  m.hy = s.hy();
  m.hz = s.hz();
  m.yaw_rad = s.yaw_rad();
  m.radius = s.radius();
  m.half_height = s.half_height();
  m.vertices = std::move(s.vertices());
  m.triangles = std::move(s.triangles());
  return m;
}

Roster from_idl(v1::RosterArrays&& s) {
  Roster m;
  m.id = std::move(s.id());
  m.radius_mm = std::move(s.radius_mm());
  m.half_height_mm = std::move(s.half_height_mm());
  m.faction = std::move(s.faction());
  m.character_type = std::move(s.character_type());
  m.archetype = std::move(s.archetype());
  return m;
}
}  // namespace

MatchInfo from_idl(v1::MatchInfo&& s) {
  MatchInfo m;
  m.protocol_version = s.protocol_version();
  m.match_id = std::move(s.match_id());
  m.scene_name = std::move(s.scene_name());
  m.tick_hz = s.tick_hz();
  m.start_tick = s.start_tick();
  m.param_table_hash = s.param_table_hash();
  m.push_policy_hash = s.push_policy_hash();
  m.param_version = s.param_version();
  m.max_clients = s.max_clients();
  m.interest_radius_m = s.interest_radius_m();
  m.world_min_x = s.world_min_x();
  m.world_min_y = s.world_min_y();
  m.world_max_x = s.world_max_x();
  m.world_max_y = s.world_max_y();
  m.state = static_cast<MatchState>(s.state());
  m.archetypes = std::move(s.archetypes());
  m.scenery.reserve(s.scenery().size());
  for (v1::SceneryShape& shape : s.scenery()) m.scenery.push_back(from_idl(std::move(shape)));
  m.roster = from_idl(std::move(s.roster()));
  return m;
}

ParamUpdate from_idl(v1::ParamUpdate&& s) {
  ParamUpdate m;
  m.request_id = s.request_id();
  m.entity = s.entity();
  m.param = std::move(s.param());
  m.value = s.value();
  m.policy_json = std::move(s.policy_json());
  return m;
}

ParamReply from_idl(v1::ParamReply&& s) {
  ParamReply m;
  m.request_id = s.request_id();
  m.ok = s.ok();
  m.error = std::move(s.error());
  m.param_version = s.param_version();
  m.tick = s.tick();
  return m;
}

ServerStats from_idl(v1::ServerStats&& s) {
  ServerStats m;
  m.tick = s.tick();
  m.tick_hz = s.tick_hz();
  m.clients = s.clients();
  m.bodies = s.bodies();
  m.tick_ms_p50 = s.tick_ms_p50();
  m.tick_ms_p99 = s.tick_ms_p99();
  m.tick_ms_max = s.tick_ms_max();
  m.overruns = s.overruns();
  m.commands_accepted = s.commands_accepted();
  m.commands_rejected = s.commands_rejected();
  m.snapshot_bytes = s.snapshot_bytes();
  m.snapshot_samples = s.snapshot_samples();
  m.push_events = s.push_events();
  m.state_hash = s.state_hash();
  m.state = static_cast<MatchState>(s.state());
  return m;
}

ContactPairs from_idl(v1::ContactPairs&& s) {
  ContactPairs m;
  m.client_id = s.client_id();
  m.tick = s.tick();
  m.pairs_near = s.pairs_near();
  m.camera_x = s.camera_x();
  m.camera_y = s.camera_y();
  m.radius_m = s.radius_m();
  m.a = std::move(s.a());
  m.b = std::move(s.b());
  m.share_a = std::move(s.share_a());
  m.depth = std::move(s.depth());
  m.push = std::move(s.push());
  return m;
}

}  // namespace throng::protocol::dds_detail
