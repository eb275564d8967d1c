#pragma once
// Field-by-field expectations for the protocol structs (messages.h has no operator==, on purpose:
// floats are compared exactly here because the transport must not change a single bit).
#include <gtest/gtest.h>

#include "throng/protocol/messages.h"

namespace throng::protocol::test {

inline void expect_same(const JoinRequest& a, const JoinRequest& b) {
  EXPECT_EQ(a.client_nonce, b.client_nonce);
  EXPECT_EQ(a.protocol_version, b.protocol_version);
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.leave, b.leave);
  EXPECT_EQ(a.client_id, b.client_id);
}

inline void expect_same(const JoinReply& a, const JoinReply& b) {
  EXPECT_EQ(a.client_nonce, b.client_nonce);
  EXPECT_EQ(a.result, b.result);
  EXPECT_EQ(a.reason, b.reason);
  EXPECT_EQ(a.client_id, b.client_id);
  EXPECT_EQ(a.entity, b.entity);
  EXPECT_EQ(a.snapshot_partition, b.snapshot_partition);
  EXPECT_EQ(a.tick, b.tick);
  EXPECT_EQ(a.faction, b.faction);
}

inline void expect_same(const Command& a, const Command& b) {
  EXPECT_EQ(a.client_id, b.client_id);
  EXPECT_EQ(a.entity, b.entity);
  EXPECT_EQ(a.sequence, b.sequence);
  EXPECT_EQ(a.last_seen_tick, b.last_seen_tick);
  EXPECT_EQ(a.move_x, b.move_x);
  EXPECT_EQ(a.move_y, b.move_y);
  EXPECT_EQ(a.facing_rad, b.facing_rad);
  EXPECT_EQ(a.actions, b.actions);
  EXPECT_EQ(a.camera_x, b.camera_x);
  EXPECT_EQ(a.camera_y, b.camera_y);
  EXPECT_EQ(a.camera_z, b.camera_z);
}

inline void expect_same(const Snapshot& a, const Snapshot& b) {
  EXPECT_EQ(a.client_id, b.client_id);
  EXPECT_EQ(a.tick, b.tick);
  EXPECT_EQ(a.last_applied_sequence, b.last_applied_sequence);
  EXPECT_EQ(a.last_applied_tick, b.last_applied_tick);
  EXPECT_EQ(a.entity, b.entity);
  EXPECT_EQ(a.entity_x, b.entity_x);
  EXPECT_EQ(a.entity_y, b.entity_y);
  EXPECT_EQ(a.entity_z, b.entity_z);
  EXPECT_EQ(a.entity_yaw, b.entity_yaw);
  EXPECT_EQ(a.origin_x_mm, b.origin_x_mm);
  EXPECT_EQ(a.origin_y_mm, b.origin_y_mm);
  EXPECT_EQ(a.unit_mm, b.unit_mm);
  EXPECT_EQ(a.objects_in_view, b.objects_in_view);
  EXPECT_EQ(a.id_codes, b.id_codes);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.z, b.z);
  EXPECT_EQ(a.yaw, b.yaw);
  EXPECT_EQ(a.removed, b.removed);
}

inline void expect_same(const SceneryShape& a, const SceneryShape& b) {
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.archetype, b.archetype);
  EXPECT_EQ(a.softness, b.softness);
  EXPECT_EQ(a.cx, b.cx);
  EXPECT_EQ(a.cy, b.cy);
  EXPECT_EQ(a.cz, b.cz);
  EXPECT_EQ(a.hx, b.hx);
  EXPECT_EQ(a.hy, b.hy);
  EXPECT_EQ(a.hz, b.hz);
  EXPECT_EQ(a.yaw_rad, b.yaw_rad);
  EXPECT_EQ(a.radius, b.radius);
  EXPECT_EQ(a.half_height, b.half_height);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.triangles, b.triangles);
}

inline void expect_same(const MatchInfo& a, const MatchInfo& b) {
  EXPECT_EQ(a.protocol_version, b.protocol_version);
  EXPECT_EQ(a.match_id, b.match_id);
  EXPECT_EQ(a.scene_name, b.scene_name);
  EXPECT_EQ(a.tick_hz, b.tick_hz);
  EXPECT_EQ(a.start_tick, b.start_tick);
  EXPECT_EQ(a.param_table_hash, b.param_table_hash);
  EXPECT_EQ(a.push_policy_hash, b.push_policy_hash);
  EXPECT_EQ(a.param_version, b.param_version);
  EXPECT_EQ(a.max_clients, b.max_clients);
  EXPECT_EQ(a.interest_radius_m, b.interest_radius_m);
  EXPECT_EQ(a.world_min_x, b.world_min_x);
  EXPECT_EQ(a.world_min_y, b.world_min_y);
  EXPECT_EQ(a.world_max_x, b.world_max_x);
  EXPECT_EQ(a.world_max_y, b.world_max_y);
  EXPECT_EQ(a.state, b.state);
  EXPECT_EQ(a.archetypes, b.archetypes);
  ASSERT_EQ(a.scenery.size(), b.scenery.size());
  for (std::size_t i = 0; i < a.scenery.size(); ++i) expect_same(a.scenery[i], b.scenery[i]);
  EXPECT_EQ(a.roster.id, b.roster.id);
  EXPECT_EQ(a.roster.radius_mm, b.roster.radius_mm);
  EXPECT_EQ(a.roster.half_height_mm, b.roster.half_height_mm);
  EXPECT_EQ(a.roster.faction, b.roster.faction);
  EXPECT_EQ(a.roster.character_type, b.roster.character_type);
  EXPECT_EQ(a.roster.archetype, b.roster.archetype);
}

inline void expect_same(const ParamUpdate& a, const ParamUpdate& b) {
  EXPECT_EQ(a.request_id, b.request_id);
  EXPECT_EQ(a.entity, b.entity);
  EXPECT_EQ(a.param, b.param);
  EXPECT_EQ(a.value, b.value);
  EXPECT_EQ(a.policy_json, b.policy_json);
}

inline void expect_same(const ParamReply& a, const ParamReply& b) {
  EXPECT_EQ(a.request_id, b.request_id);
  EXPECT_EQ(a.ok, b.ok);
  EXPECT_EQ(a.error, b.error);
  EXPECT_EQ(a.param_version, b.param_version);
  EXPECT_EQ(a.tick, b.tick);
}

inline void expect_same(const ServerStats& a, const ServerStats& b) {
  EXPECT_EQ(a.tick, b.tick);
  EXPECT_EQ(a.tick_hz, b.tick_hz);
  EXPECT_EQ(a.clients, b.clients);
  EXPECT_EQ(a.bodies, b.bodies);
  EXPECT_EQ(a.tick_ms_p50, b.tick_ms_p50);
  EXPECT_EQ(a.tick_ms_p99, b.tick_ms_p99);
  EXPECT_EQ(a.tick_ms_max, b.tick_ms_max);
  EXPECT_EQ(a.overruns, b.overruns);
  EXPECT_EQ(a.commands_accepted, b.commands_accepted);
  EXPECT_EQ(a.commands_rejected, b.commands_rejected);
  EXPECT_EQ(a.snapshot_bytes, b.snapshot_bytes);
  EXPECT_EQ(a.snapshot_samples, b.snapshot_samples);
  EXPECT_EQ(a.push_events, b.push_events);
  EXPECT_EQ(a.state_hash, b.state_hash);
  EXPECT_EQ(a.state, b.state);
}

inline void expect_same(const ContactPairs& a, const ContactPairs& b) {
  EXPECT_EQ(a.client_id, b.client_id);
  EXPECT_EQ(a.tick, b.tick);
  EXPECT_EQ(a.pairs_near, b.pairs_near);
  EXPECT_EQ(a.camera_x, b.camera_x);
  EXPECT_EQ(a.camera_y, b.camera_y);
  EXPECT_EQ(a.radius_m, b.radius_m);
  EXPECT_EQ(a.a, b.a);
  EXPECT_EQ(a.b, b.b);
  EXPECT_EQ(a.share_a, b.share_a);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.push, b.push);
}

}  // namespace throng::protocol::test
