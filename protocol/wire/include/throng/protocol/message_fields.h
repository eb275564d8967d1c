#pragma once
// The one list of each message's fields (messages.h), in the IDL's order. The DDS conversions
// (protocol/dds/src/conversions.cpp) and the tests' field-by-field comparison
// (tests/protocol/message_equality.h) both expand these lists instead of naming every field again,
// and the static_asserts below fail the build when a struct gains a field its list lacks. Why
// macros: the fastddsgen types expose a field only through an accessor of the same name, which a
// member pointer cannot reach; an X-macro is the one spelling both sides can share.
//
// THRONG_<MESSAGE>_FIELDS(X) expands X(field) once per field that travels on the wire;
// THRONG_<MESSAGE>_LOCAL_FIELDS(X) lists the fields the server's transport fills in, never sent.
#include <cstddef>
#include <utility>

#include "throng/protocol/messages.h"

#define THRONG_JOIN_REQUEST_FIELDS(X) X(client_nonce) X(protocol_version) X(name) X(leave) X(client_id)
#define THRONG_JOIN_REQUEST_LOCAL_FIELDS(X) X(sender) X(identity)

#define THRONG_JOIN_REPLY_FIELDS(X) \
  X(client_nonce) X(result) X(reason) X(client_id) X(entity) X(snapshot_partition) X(tick) X(faction)

#define THRONG_COMMAND_FIELDS(X)                                                                           \
  X(client_id) X(entity) X(sequence) X(last_seen_tick) X(move_x) X(move_y) X(facing_rad) X(actions) X(camera_x) \
  X(camera_y) X(camera_z)
#define THRONG_COMMAND_LOCAL_FIELDS(X) X(sender)

#define THRONG_SNAPSHOT_FIELDS(X)                                                                             \
  X(client_id) X(tick) X(last_applied_sequence) X(last_applied_tick) X(entity) X(entity_x) X(entity_y)        \
  X(entity_z) X(entity_yaw) X(origin_x_mm) X(origin_y_mm) X(unit_mm) X(objects_in_view) X(id_codes) X(x) X(y) \
  X(z) X(yaw) X(removed)

#define THRONG_CONTACT_PAIRS_FIELDS(X) \
  X(client_id) X(tick) X(pairs_near) X(camera_x) X(camera_y) X(radius_m) X(a) X(b) X(share_a) X(depth) X(push)

#define THRONG_SCENERY_SHAPE_FIELDS(X)                                                                          \
  X(id) X(kind) X(archetype) X(softness) X(cx) X(cy) X(cz) X(hx) X(hy) X(hz) X(yaw_rad) X(radius) X(half_height) \
  X(vertices) X(triangles)

#define THRONG_ROSTER_FIELDS(X) X(id) X(radius_mm) X(half_height_mm) X(faction) X(character_type) X(archetype)

#define THRONG_MATCH_INFO_FIELDS(X)                                                                             \
  X(protocol_version) X(match_id) X(scene_name) X(tick_hz) X(start_tick) X(param_table_hash) X(push_policy_hash) \
  X(param_version) X(max_clients) X(interest_radius_m) X(world_min_x) X(world_min_y) X(world_max_x)              \
  X(world_max_y) X(state) X(archetypes) X(scenery) X(roster)

#define THRONG_PARAM_UPDATE_FIELDS(X) X(request_id) X(entity) X(param) X(value) X(policy_json)
#define THRONG_PARAM_UPDATE_LOCAL_FIELDS(X) X(sender)

#define THRONG_PARAM_REPLY_FIELDS(X) X(request_id) X(ok) X(error) X(param_version) X(tick)

#define THRONG_SERVER_STATS_FIELDS(X)                                                                     \
  X(tick) X(tick_hz) X(clients) X(bodies) X(tick_ms_p50) X(tick_ms_p99) X(tick_ms_max) X(overruns)        \
  X(commands_accepted) X(commands_rejected) X(snapshot_bytes) X(snapshot_samples) X(push_events) X(state_hash) \
  X(state)

#define THRONG_TICK_ENTRY_FIELDS(X) X(match_id) X(tick) X(entry)
#define THRONG_STANDBY_REQUEST_FIELDS(X) X(standby_nonce) X(have_tick)
#define THRONG_STANDBY_SYNC_FIELDS(X) X(standby_nonces) X(tick) X(epoch) X(header_json) X(checkpoint)
#define THRONG_PRIMARY_CLAIM_FIELDS(X) X(match_id) X(epoch) X(tick) X(server_id)

namespace throng::protocol::detail {

// Counts an aggregate's fields: the largest N for which T{x1, ..., xN} compiles when each x
// converts to anything. Only ever used in unevaluated contexts, so the conversion has no body.
struct AnyField {
  template <class T>
  operator T() const;  // NOLINT(google-explicit-constructor): converting to every field is its job
};

template <class T, std::size_t... I>
constexpr bool brace_initializable(std::index_sequence<I...>) {
  return requires { T{(static_cast<void>(I), AnyField{})...}; };
}

template <class T, std::size_t N = 0>
constexpr std::size_t aggregate_field_count() {
  if constexpr (brace_initializable<T>(std::make_index_sequence<N + 1>{})) return aggregate_field_count<T, N + 1>();
  else return N;
}

}  // namespace throng::protocol::detail

#define THRONG_COUNT_FIELD(field) +1
#define THRONG_CHECK_FIELD_LIST(Type, count)                                            \
  static_assert(::throng::protocol::detail::aggregate_field_count<Type>() == 0 + count, \
                "a field of " #Type " is missing from its list in message_fields.h")

namespace throng::protocol {

THRONG_CHECK_FIELD_LIST(JoinRequest, THRONG_JOIN_REQUEST_FIELDS(THRONG_COUNT_FIELD)
                                         THRONG_JOIN_REQUEST_LOCAL_FIELDS(THRONG_COUNT_FIELD));
THRONG_CHECK_FIELD_LIST(JoinReply, THRONG_JOIN_REPLY_FIELDS(THRONG_COUNT_FIELD));
THRONG_CHECK_FIELD_LIST(Command, THRONG_COMMAND_FIELDS(THRONG_COUNT_FIELD) THRONG_COMMAND_LOCAL_FIELDS(THRONG_COUNT_FIELD));
THRONG_CHECK_FIELD_LIST(Snapshot, THRONG_SNAPSHOT_FIELDS(THRONG_COUNT_FIELD));
THRONG_CHECK_FIELD_LIST(ContactPairs, THRONG_CONTACT_PAIRS_FIELDS(THRONG_COUNT_FIELD));
THRONG_CHECK_FIELD_LIST(SceneryShape, THRONG_SCENERY_SHAPE_FIELDS(THRONG_COUNT_FIELD));
THRONG_CHECK_FIELD_LIST(Roster, THRONG_ROSTER_FIELDS(THRONG_COUNT_FIELD));
THRONG_CHECK_FIELD_LIST(MatchInfo, THRONG_MATCH_INFO_FIELDS(THRONG_COUNT_FIELD));
THRONG_CHECK_FIELD_LIST(ParamUpdate, THRONG_PARAM_UPDATE_FIELDS(THRONG_COUNT_FIELD)
                                         THRONG_PARAM_UPDATE_LOCAL_FIELDS(THRONG_COUNT_FIELD));
THRONG_CHECK_FIELD_LIST(ParamReply, THRONG_PARAM_REPLY_FIELDS(THRONG_COUNT_FIELD));
THRONG_CHECK_FIELD_LIST(ServerStats, THRONG_SERVER_STATS_FIELDS(THRONG_COUNT_FIELD));
THRONG_CHECK_FIELD_LIST(TickEntry, THRONG_TICK_ENTRY_FIELDS(THRONG_COUNT_FIELD));
THRONG_CHECK_FIELD_LIST(StandbyRequest, THRONG_STANDBY_REQUEST_FIELDS(THRONG_COUNT_FIELD));
THRONG_CHECK_FIELD_LIST(StandbySync, THRONG_STANDBY_SYNC_FIELDS(THRONG_COUNT_FIELD));
THRONG_CHECK_FIELD_LIST(PrimaryClaim, THRONG_PRIMARY_CLAIM_FIELDS(THRONG_COUNT_FIELD));

}  // namespace throng::protocol
