// Match checkpoints: the whole simulation state of a match (layout: CHECKPOINT.md next to this
// file). Restoring one into a Match built from the same scene and config makes tick() continue
// bit-identically (state hashes, outbox, snapshot bytes).
//
// Saved (match section): shutdown flag and the pending match-info republish, reject counters and
// the accepted total, per body (dense order) the yaw and the controlling client, the match info's
// mutable part (state, param_version, policy hash, roster faction / character type, scenery
// softness), every client record ever seen (ids, nonce, name, partition, entity, sequences, rate
// counter, camera, the NPC parameters to restore, brace state, command counters), the NPC AI
// (npc_ai_state.cpp) and the snapshot builder's per-client baselines (snapshot_builder.cpp).
// Derived on restore from the world: id_values, dense_of_slot. Fixed by scene/config (checked by
// the header's hashes, not saved): roster_of_slot, timeout_ticks, player_importance, the rest of
// the match info. Not saved:
//  - the input queue: inputs not yet drained are future inputs (the match log records them in
//    the tick that drains them), and its drop counter is a statistic;
//  - last_inputs(), the TickReport, worker scratches / totals, cameras / perm / scratch vectors:
//    all rewritten by the next tick before they are read;
//  - the snapshot sink and the match id: they belong to the process hosting the match.
#include <algorithm>
#include <cstring>
#include <exception>
#include <string>

#include "match_impl.h"
#include "match_info.h"
#include "throng/core/byte_io.h"
#include "throng/world/world.h"

namespace throng::match {
namespace {

constexpr std::uint32_t kMagic = 0x4B434D54;  // "TMCK" in the file
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kMaxClientsEver = 1u << 24;

template <class T>
std::uint64_t mix(std::uint64_t h, const T& v) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  for (unsigned char c : b) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::string hex(std::uint64_t v) {
  static const char* digits = "0123456789abcdef";
  std::string s(16, '0');
  for (int i = 15; i >= 0; --i, v >>= 4) s[static_cast<std::size_t>(i)] = digits[v & 15];
  return s;
}

void put_client(ByteWriter& w, const ClientRecord& c) {
  w.put(c.id);
  w.put(c.nonce);
  w.put_string(c.name);
  w.put_string(c.partition);
  w.put(c.entity.value);
  w.put(c.faction);
  w.put(static_cast<std::uint8_t>(c.connected));
  w.put(c.joined_tick);
  w.put(c.last_activity_tick);
  w.put(c.last_applied_sequence);
  w.put(c.last_applied_tick);
  w.put(c.rate_tick);
  w.put(c.accepted_in_tick);
  w.put(static_cast<std::uint8_t>(c.has_camera));
  w.put(c.camera.x);
  w.put(c.camera.y);
  w.put(c.camera.z);
  w.put(c.npc_character_type);
  w.put(c.npc_importance);
  w.put(c.base_weight_kg);
  w.put(static_cast<std::uint8_t>(c.bracing));
  w.put(c.commands_accepted);
  w.put(c.commands_rejected);
}

ClientRecord get_client(ByteReader& r) {
  ClientRecord c;
  c.id = r.get<std::uint32_t>("client id");
  c.nonce = r.get<std::uint64_t>("client nonce");
  c.name = r.get_string("client name", 4096);
  c.partition = r.get_string("client partition", 4096);
  c.entity = ObjectId{r.get<std::uint32_t>("client entity")};
  c.faction = r.get<std::uint8_t>("client faction");
  c.connected = r.get_bool("client connected");
  c.joined_tick = r.get<std::uint64_t>("client joined tick");
  c.last_activity_tick = r.get<std::uint64_t>("client activity tick");
  c.last_applied_sequence = r.get<std::uint32_t>("client sequence");
  c.last_applied_tick = r.get<std::uint64_t>("client applied tick");
  c.rate_tick = r.get<std::uint64_t>("client rate tick");
  c.accepted_in_tick = r.get<std::uint32_t>("client rate count");
  c.has_camera = r.get_bool("client has camera");
  c.camera.x = r.get<double>("client camera");
  c.camera.y = r.get<double>("client camera");
  c.camera.z = r.get<double>("client camera");
  c.npc_character_type = r.get<double>("client npc character type");
  c.npc_importance = r.get<double>("client npc importance");
  c.base_weight_kg = r.get<double>("client base weight");
  c.bracing = r.get_bool("client bracing");
  c.commands_accepted = r.get<std::uint64_t>("client accepted");
  c.commands_rejected = r.get<std::uint64_t>("client rejected");
  return c;
}

}  // namespace

void Match::Impl::compute_checkpoint_hashes() {
  // Scene: the table and initial policy (as MatchInfo hashes them), the scene name, the scenery
  // count and the world's state hash at construction, which covers every body's id, spawn pose,
  // size and initial push coefficients.
  std::uint64_t h = 14695981039346656037ull;
  h = mix(h, info.param_table_hash);
  h = mix(h, info.push_policy_hash);
  h = fnv1a64(scene.name, h);
  h = mix(h, static_cast<std::uint64_t>(info.scenery.size()));
  h = mix(h, static_cast<std::uint64_t>(world().body_count()));
  h = mix(h, world().state_hash());
  scene_hash = h;
  // Config: every field that changes results (worker_threads does not, by design).
  std::uint64_t c = 14695981039346656037ull;
  c = mix(c, config.tick_hz); c = mix(c, config.max_clients); c = mix(c, config.client_timeout_s);
  c = mix(c, config.max_commands_per_tick); c = mix(c, config.player_speed_mps); c = mix(c, config.npc_speed_mps);
  c = mix(c, config.camera_limit_m); c = mix(c, config.seed);
  const InterestConfig& in = config.interest;
  c = mix(c, in.radius_m); c = mix(c, in.exit_hysteresis); c = mix(c, in.budget_bytes);
  c = mix(c, in.keepalive_ticks); c = mix(c, in.removed_repeat);
  config_hash = c;
}

void Match::Impl::save_checkpoint(std::vector<std::uint8_t>& out) const {
  ByteWriter w(out, ByteWriter::kOverwrite);  // = cleared first, without re-zeroing the bytes
  w.put(kMagic);
  w.put(kVersion);
  w.put(scene_hash);
  w.put(config_hash);
  w.put(static_cast<std::uint32_t>(world().body_count()));
  w.put(ticks);
  // World section, length-prefixed so a reader can skip it or hand it to diff_world_states.
  const std::size_t len_at = w.size();
  w.put(std::uint32_t{0});
  world().save_state(w);
  w.patch_u32(len_at, static_cast<std::uint32_t>(w.size() - len_at - 4));

  w.put(static_cast<std::uint8_t>(shutting_down));
  w.put(static_cast<std::uint8_t>(info_dirty));
  w.put_array(std::span<const std::uint64_t>(rejected));
  w.put(accepted_total);
  w.put_array(yaw);
  w.put_array(controller);
  w.put(static_cast<std::uint8_t>(info.state));
  w.put(info.param_version);
  w.put(info.push_policy_hash);
  w.put_array(info.roster.faction);
  w.put_array(info.roster.character_type);
  w.put(static_cast<std::uint32_t>(info.scenery.size()));
  for (const protocol::SceneryShape& s : info.scenery) w.put(s.softness);
  const std::deque<ClientRecord>& records = clients.records();
  w.put(static_cast<std::uint32_t>(records.size()));
  for (const ClientRecord& c : records) put_client(w, c);
  ai.save_state(w);
  snapshots.save_state(w);
  w.finish();
}

void Match::Impl::restore_checkpoint(std::span<const std::uint8_t> bytes) {
  ByteReader r(bytes);
  const auto magic = r.get<std::uint32_t>("magic");
  if (magic != kMagic) r.fail("not a match checkpoint (magic " + hex(magic) + ", expected " + hex(kMagic) + ")");
  const auto version = r.get<std::uint32_t>("version");
  if (version != kVersion) {
    r.fail("checkpoint version " + std::to_string(version) + ", this build reads version " + std::to_string(kVersion));
  }
  const auto their_scene = r.get<std::uint64_t>("scene hash");
  const auto their_config = r.get<std::uint64_t>("config hash");
  const auto n = r.get<std::uint32_t>("body count");
  const std::size_t my_n = world().body_count();
  if (n != my_n) {
    throw CheckpointError("checkpoint is from another scene: it has " + std::to_string(n) + " bodies, this match " +
                          std::to_string(my_n));
  }
  if (their_scene != scene_hash) {
    throw CheckpointError("checkpoint is from another scene: scene hash " + hex(their_scene) + ", this match " +
                          hex(scene_hash) + " (parameter table, policy, scenery or spawn layout differ)");
  }
  if (their_config != config_hash) {
    throw CheckpointError("checkpoint is from a match with another config: config hash " + hex(their_config) +
                          ", this match " + hex(config_hash));
  }
  const auto their_ticks = r.get<std::uint64_t>("tick");
  const std::uint32_t world_len = r.get<std::uint32_t>("world section length");
  const std::span<const std::uint8_t> world_bytes(r.take(world_len, "world section"), world_len);

  // Decode the match section into staging copies first: nothing changes until all of it decoded.
  const bool their_shutdown = r.get_bool("shutdown flag");
  const bool their_info_dirty = r.get_bool("match info dirty");
  std::vector<std::uint64_t> their_rejected;
  r.get_array_exact(their_rejected, "reject counters", kRejectReasonCount);
  const auto their_accepted = r.get<std::uint64_t>("accepted total");
  std::vector<float> their_yaw;
  std::vector<std::uint32_t> their_controller;
  r.get_array_exact(their_yaw, "yaw", n);
  r.get_array_exact(their_controller, "controller", n);
  const auto state = r.get<std::uint8_t>("match state");
  if (state > 1) r.fail("match state " + std::to_string(state));
  const auto param_version = r.get<std::uint32_t>("param version");
  const auto policy_hash_now = r.get<std::uint64_t>("policy hash");
  std::vector<std::uint8_t> roster_faction, roster_type;
  r.get_array_exact(roster_faction, "roster factions", info.roster.faction.size());
  r.get_array_exact(roster_type, "roster character types", info.roster.character_type.size());
  std::vector<float> softness(r.get_count("scenery softness", info.scenery.size(), 4));
  if (softness.size() != info.scenery.size()) r.fail("scenery count differs from this match's");
  for (float& s : softness) s = r.get<float>("scenery softness");
  std::deque<ClientRecord> records;
  const std::uint32_t n_clients = r.get_count("clients", kMaxClientsEver, 100);
  for (std::size_t k = 0; k < n_clients; ++k) {
    records.push_back(get_client(r));
    if (records.back().id != k + 1) r.fail("client ids are not 1, 2, 3, ...");
  }
  for (std::uint32_t c : their_controller) {
    if (c > records.size()) r.fail("a body is controlled by client " + std::to_string(c) + ", never seen");
  }
  NpcAi staged_ai = ai;
  staged_ai.restore_state(r, n);
  SnapshotBuilder staged_snapshots(config.interest);
  // The builder's tables grow to at most 1.25x the largest object index, at least 1,024
  // (interest_grid.cpp): anything beyond twice that is corrupt.
  staged_snapshots.restore_state(r, std::max<std::size_t>(1024, 2 * dense_of_slot.size()));
  if (r.remaining() != 0) r.fail(std::to_string(r.remaining()) + " bytes after the end of the checkpoint");

  world().restore_state(world_bytes);  // throws before changing anything; the last thing that may throw

  // Commit.
  ticks = their_ticks;
  shutting_down = their_shutdown;
  info_dirty = their_info_dirty;
  std::copy(their_rejected.begin(), their_rejected.end(), rejected.begin());
  accepted_total = their_accepted;
  yaw = std::move(their_yaw);
  controller = std::move(their_controller);
  info.state = static_cast<protocol::MatchState>(state);
  info.param_version = param_version;
  info.push_policy_hash = policy_hash_now;
  info.roster.faction = std::move(roster_faction);
  info.roster.character_type = std::move(roster_type);
  for (std::size_t s = 0; s < softness.size(); ++s) info.scenery[s].softness = softness[s];
  clients.restore(std::move(records));
  ai = std::move(staged_ai);
  snapshots = std::move(staged_snapshots);
  const World& w = world();
  for (std::size_t d = 0; d < n; ++d) {
    const ObjectId oid = w.id_at(d);
    id_values[d] = oid.value;
    if (dense_of_slot.size() <= oid.index()) dense_of_slot.resize(oid.index() + 1, kNoDense);
    dense_of_slot[oid.index()] = static_cast<std::uint32_t>(d);
  }
  report = TickReport{};
}

}  // namespace throng::match
