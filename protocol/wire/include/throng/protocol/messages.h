#pragma once
// The protocol's messages as plain C++ structs: what the match logic, the bots and the tests
// exchange. They mirror the IDL in protocol/idl/throng.idl field by field; only the DDS edge
// (protocol/dds) converts between these and the fastddsgen types, so nothing in the simulation or
// the match logic ever includes a DDS header.
//
// Units on the wire: metres as float for inputs a client sends (a client is never trusted, so the
// server validates every value), quantized integers for the poses the server sends (codec.h).
#include <array>
#include <compare>
#include <cstdint>
#include <string>
#include <vector>

namespace throng::protocol {

// Bumped on any incompatible change of a message or of the snapshot encoding. A client with a
// different version is refused at join with JoinResult::bad_version.
inline constexpr std::uint32_t kProtocolVersion = 1;

// Topic names. The version is part of the name so two incompatible builds never match at all.
inline constexpr const char* kTopicMatchInfo = "throng_v1_match_info";
inline constexpr const char* kTopicJoinRequest = "throng_v1_join_request";
inline constexpr const char* kTopicJoinReply = "throng_v1_join_reply";
inline constexpr const char* kTopicCommand = "throng_v1_command";
inline constexpr const char* kTopicSnapshot = "throng_v1_snapshot";
inline constexpr const char* kTopicParamUpdate = "throng_v1_param_update";
inline constexpr const char* kTopicParamReply = "throng_v1_param_reply";
inline constexpr const char* kTopicServerStats = "throng_v1_server_stats";
inline constexpr const char* kTopicContacts = "throng_v1_contacts";
// Server to server only (a hot standby; DDS Security grants them to the server identity alone).
inline constexpr const char* kTopicTickInputs = "throng_v1_tick_inputs";
inline constexpr const char* kTopicStandbyRequest = "throng_v1_standby_request";
inline constexpr const char* kTopicStandbySync = "throng_v1_standby_sync";
inline constexpr const char* kTopicPrimary = "throng_v1_primary";

// The DDS participant a message came from: the GUID prefix of the writer of the sample, filled in
// by the server's transport from the sample's metadata. Never part of a message a client
// serializes, so a client cannot set it by writing a field; a client_id belongs to the participant
// that joined it (match_joins.cpp). All zeros: not received over DDS (tests, tools).
// Without DDS Security a GUID prefix can still be forged on the wire by a crafted RTPS packet; with
// it, the participant behind the prefix is authenticated (README, "Security").
struct ParticipantKey {
  std::array<std::uint8_t, 12> bytes{};
  auto operator<=>(const ParticipantKey&) const = default;
};

// Snapshot partitions of clients whose join carried an authenticated identity (DDS Security):
// kIdentityPartitionPrefix + certificate CN + "_" + client id in decimal, e.g.
// throng_p_player-alice_7. A player's permissions (throng-pki) grant it exactly these names, which
// can be written before the join.
inline constexpr const char* kIdentityPartitionPrefix = "throng_p_";

// --- join / leave (client -> server, reliable) ----------------------------------------------
struct JoinRequest {
  std::uint64_t client_nonce = 0;  // random per client process+bot; keys the reply
  std::uint32_t protocol_version = kProtocolVersion;
  std::string name;                // free text for logs, at most 64 bytes
  bool leave = false;              // true: the client leaves (client_id below)
  std::uint32_t client_id = 0;     // leave only
  // Filled in by the server's transport, not sent: who wrote the request, and (with DDS Security)
  // the common name of its authenticated certificate, empty without Security. The client's
  // snapshot partition follows from the identity, so a player's permissions can name it before the
  // join.
  ParticipantKey sender;
  std::string identity;
};

enum class JoinResult : std::uint8_t {
  accepted = 0,
  match_full = 1,
  bad_version = 2,
  shutting_down = 3,
  bad_request = 4,  // malformed (empty nonce, name too long, leave for an unknown client)
  left = 5,         // reply to a leave
  // A join or leave naming a client (nonce, client id) that another participant owns. Counted, and
  // never published: the reply topic is keyed by nonce, so a refusal would overwrite the owner's
  // own accepted reply.
  foreign_participant = 6,
};
const char* to_string(JoinResult r);

// server -> clients, reliable + transient-local keyed by client_nonce, so a late joiner also
// learns which entity each client controls.
struct JoinReply {
  std::uint64_t client_nonce = 0;
  JoinResult result = JoinResult::accepted;
  std::string reason;              // human-readable when refused
  std::uint32_t client_id = 0;     // 1.., never reused within a match
  std::uint32_t entity = 0;        // the ObjectId value the client controls
  std::string snapshot_partition;  // DDS partition this client's snapshots are written in
  std::uint64_t tick = 0;          // server tick when the reply was made
  std::uint8_t faction = 0;        // the side the entity fights for
};

// --- commands (client -> server, best-effort) -------------------------------------------------
// Action bits. Unknown bits are a validation error (bad_actions).
inline constexpr std::uint32_t kActionSprint = 1u << 0;  // move at 1.5x speed
inline constexpr std::uint32_t kActionBrace = 1u << 1;   // stand firm: counts as heavier while held
// Not a game action: "send me the contact pairs near my camera" (the ContactPairs topic, a debug
// overlay). It never changes the simulation; the server grants it to a few clients at a time.
inline constexpr std::uint32_t kActionContacts = 1u << 2;
inline constexpr std::uint32_t kKnownActions = kActionSprint | kActionBrace | kActionContacts;

struct Command {
  std::uint32_t client_id = 0;
  std::uint32_t entity = 0;          // must be the entity the server gave this client
  std::uint32_t sequence = 0;        // strictly increasing per client, starts at 1
  std::uint64_t last_seen_tick = 0;  // newest snapshot tick the client has received
  float move_x = 0.0f;               // desired move as a fraction of the entity's max speed;
  float move_y = 0.0f;               //   |(move_x, move_y)| <= 1
  float facing_rad = 0.0f;           // in [-pi, pi]
  std::uint32_t actions = 0;         // kAction* bits
  float camera_x = 0.0f;             // camera position in world metres (interest management and
  float camera_y = 0.0f;             //   the engine's camera-distance parameter)
  float camera_z = 0.0f;
  ParticipantKey sender;             // filled in by the server's transport, not sent (see above)
};

// --- snapshots (server -> one client, best-effort, one sample per client per tick) -----------
// Poses are quantized and stored structure-of-arrays (codec.h says exactly how): a pose costs
// 9 bytes. Only objects near the client's camera are sent, most important first within a byte
// budget; objects that did not move since the client last got them are skipped.
struct Snapshot {
  std::uint32_t client_id = 0;
  std::uint64_t tick = 0;
  std::uint32_t last_applied_sequence = 0;  // newest command sequence of this client applied
  std::uint64_t last_applied_tick = 0;      // tick that command was applied in
  std::uint32_t entity = 0;                 // the client's own entity (0 after it is gone)
  float entity_x = 0, entity_y = 0, entity_z = 0, entity_yaw = 0;  // own pose, unquantized
  std::int32_t origin_x_mm = 0;             // quantization origin of the pose arrays
  std::int32_t origin_y_mm = 0;
  std::uint16_t unit_mm = 1;                // position step (1 mm unless the interest area is huge)
  std::uint32_t objects_in_view = 0;        // objects inside the interest area this tick
  std::vector<std::uint16_t> id_codes;      // delta-coded object ids (codec.h)
  std::vector<std::int16_t> x;              // (x - origin_x) / unit
  std::vector<std::int16_t> y;
  std::vector<std::int16_t> z;              // z / unit (absolute, +-32 m at 1 mm)
  std::vector<std::uint8_t> yaw;            // yaw * 256 / 2pi
  std::vector<std::uint32_t> removed;       // ids that left the interest area or were destroyed
};

// --- contact pairs (server -> one opted-in client, best-effort, one sample per tick) ----------
// The body pairs the solver pushed apart this tick nearest the client's camera (a debug overlay:
// collision shapes, contact planes and push ratios). Sent only while the client's newest applied
// command carries kActionContacts and the server granted it (contacts.h has the units).
struct ContactPairs {
  std::uint32_t client_id = 0;
  std::uint64_t tick = 0;
  std::uint32_t pairs_near = 0;         // body pairs within radius_m of the camera, before the cap
  float camera_x = 0, camera_y = 0;     // the centre the pairs were chosen around
  float radius_m = 0;
  std::vector<std::uint32_t> a;         // object ids of each pair, nearest the camera first
  std::vector<std::uint32_t> b;
  std::vector<std::uint16_t> share_a;   // fraction of the push that moved a, * kShareScale
  std::vector<std::uint16_t> depth;     // penetration at the start of the solve, kContactUnitM steps
  std::vector<std::uint16_t> push;      // total push of the pair this tick, kContactUnitM steps
};

// --- match info (server -> all, reliable, transient-local, keep last 1) ----------------------
enum class ShapeKind : std::uint8_t { box = 0, cylinder = 1, mesh = 2 };

struct SceneryShape {
  std::uint32_t id = 0;
  ShapeKind kind = ShapeKind::box;
  std::string archetype;
  float softness = 0.0f;                     // 0 = hard; >0 = soft fixed body (bush, cushion)
  float cx = 0, cy = 0, cz = 0;              // box, cylinder
  float hx = 0, hy = 0, hz = 0, yaw_rad = 0; // box
  float radius = 0, half_height = 0;         // cylinder
  std::vector<float> vertices;               // mesh: x,y,z triples
  std::vector<std::uint32_t> triangles;      // mesh: index triples
};

// Static facts about a movable, so a client can draw it (structure-of-arrays, same index).
struct Roster {
  std::vector<std::uint32_t> id;
  std::vector<std::uint16_t> radius_mm;
  std::vector<std::uint16_t> half_height_mm;  // 0 = sphere
  std::vector<std::uint8_t> faction;
  std::vector<std::uint8_t> character_type;   // params::CharacterType value
  std::vector<std::uint8_t> archetype;        // index into MatchInfo::archetypes
};

enum class MatchState : std::uint8_t { running = 0, ended = 1 };

struct MatchInfo {
  std::uint32_t protocol_version = kProtocolVersion;
  std::string match_id;             // unique per server run
  std::string scene_name;
  std::uint32_t tick_hz = 30;
  std::uint64_t start_tick = 0;
  std::uint64_t param_table_hash = 0;  // XXH3 of the parameter table / push policy JSON text
  std::uint64_t push_policy_hash = 0;
  std::uint32_t param_version = 0;     // +1 for every applied operator change
  std::uint32_t max_clients = 0;
  float interest_radius_m = 0;         // 0 = whole world
  float world_min_x = 0, world_min_y = 0, world_max_x = 0, world_max_y = 0;
  MatchState state = MatchState::running;
  std::vector<std::string> archetypes;
  std::vector<SceneryShape> scenery;
  Roster roster;
};

// --- operator parameter changes (operator -> server, reliable) -------------------------------
struct ParamUpdate {
  std::uint64_t request_id = 0;
  std::uint32_t entity = 0;        // object whose parameter changes (0 with policy_json)
  std::string param;               // parameter name as in the parameter table ("weight", ...)
  double value = 0.0;
  std::string policy_json;         // non-empty: replace the push policy with this document
  // Filled in by the server's transport, not sent. The server's edge decides who may change
  // parameters (an operator); the match itself never reads it, so the match log does not keep it.
  ParticipantKey sender;
};

struct ParamReply {
  std::uint64_t request_id = 0;
  bool ok = false;
  std::string error;               // why it was rejected
  std::uint32_t param_version = 0; // after applying
  std::uint64_t tick = 0;          // the tick it took effect in
};

// --- server statistics (server -> all, reliable, keep last 1, once per second) ---------------
struct ServerStats {
  std::uint64_t tick = 0;
  std::uint32_t tick_hz = 0;
  std::uint32_t clients = 0;
  std::uint32_t bodies = 0;
  float tick_ms_p50 = 0, tick_ms_p99 = 0, tick_ms_max = 0;  // over the last second
  std::uint64_t overruns = 0;
  std::uint64_t commands_accepted = 0;
  std::uint64_t commands_rejected = 0;
  std::uint64_t snapshot_bytes = 0;
  std::uint64_t snapshot_samples = 0;
  std::uint64_t push_events = 0;
  std::uint64_t state_hash = 0;
  MatchState state = MatchState::running;
};

// --- hot standby: primary server <-> standby servers (docs/design/standby.md) -----------------
// One tick as the primary applied it: the match log's tick entry (matchlog::encode_tick: the
// inputs in applied order, the state hash, flags). Reliable and ordered, primary -> standbys.
struct TickEntry {
  std::string match_id;  // a standby follows one match; another primary on the domain is not it
  std::uint64_t tick = 0;
  std::vector<std::uint8_t> entry;
};

// A standby asks the primary for the match: when it starts, and when its chain broke (a divergent
// tick, entries it missed). Reliable, standby -> primary.
struct StandbyRequest {
  std::uint64_t standby_nonce = 0;  // random per standby process; keys the answer
  std::uint64_t have_tick = 0;      // the last tick the standby applied (0: none)
};

// The primary's answer: its match log header (JSON text: scene, config, match id, build) and a
// checkpoint saved after `tick`, with the snapshot baselines. Reliable, primary -> standbys.
struct StandbySync {
  // Every standby this answer is for (requests that arrived by the same tick share one answer: a
  // keep-last-1 writer would replace one answer with the next before it left).
  std::vector<std::uint64_t> standby_nonces;
  std::uint64_t tick = 0;
  std::uint64_t epoch = 0;  // the primary's (PrimaryClaim); a standby that takes over claims epoch + 1
  std::vector<std::uint8_t> header_json;
  std::vector<std::uint8_t> checkpoint;
};

// Which server hosts a match: every primary writes its claim when it starts hosting (epoch 1 for a
// new match, the highest epoch a standby has seen + 1 after a takeover) and reads the others'. A
// primary that sees a claim above its own for its match, by epoch and then by server id (two
// standbys that took over at once), has been replaced and stops at once: no two servers keep
// hosting one match. Standbys read the claims too, to know the epoch to claim. Reliable,
// transient-local, server to server only.
struct PrimaryClaim {
  std::string match_id;
  std::uint64_t epoch = 0;
  std::uint64_t tick = 0;       // the match tick the claim was made at
  std::uint64_t server_id = 0;  // random per server process: orders two claims of one epoch
};

}  // namespace throng::protocol
