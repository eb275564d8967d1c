// Match checkpoints: the whole simulation state of a match (layout: CHECKPOINT.md next to this
// file). Restoring one into a Match built from the same scene and config makes tick() continue
// bit-identically (state hashes, outbox, snapshot bytes). Restoring with SnapshotBaselines::reset
// skips the snapshot section and the interest settings' hash: world, AI, clients and state hashes
// continue bit-identically; snapshots start from empty baselines under this match's settings.
//
// Saved (match section): shutdown flag and the pending match-info republish, reject counters and
// the accepted total, per body (dense order) the yaw and the controlling client, the match info's
// mutable part (state, param_version, policy hash, roster faction / character type, scenery
// softness), the next client id and the connected clients' records (ids, nonce, name, partition,
// entity, sequences, rate counter, camera, the NPC parameters to restore, brace state, command
// counters, owner), the NPC AI
// (npc_ai_state.cpp) and the snapshot builder's per-client baselines (snapshot_builder.cpp).
// Derived on restore from the world: id_values (the AI aligns its own order with it). Fixed by scene/config (checked by
// the header's hashes, not saved): roster_of_slot, timeout_ticks, player_importance, the rest of
// the match info. Not saved:
//  - the input queue: inputs not yet drained are future inputs (the match log records them in
//    the tick that drains them), and its drop counter is a statistic;
//  - last_inputs(), the TickReport, worker scratches / totals, cameras / perm / scratch vectors:
//    all rewritten by the next tick before they are read;
//  - the snapshot sink and the match id: they belong to the process hosting the match.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "interest_grid.h"
#include "match_impl.h"
#include "match_info.h"
#include "throng/core/byte_io.h"
#include "throng/params/object_params.h"
#include "throng/world/world.h"

namespace throng::match {
namespace {

constexpr std::uint32_t kMagic = 0x4B434D54;  // "TMCK" in the file
// 4: the NPC AI in its compact form (npc_ai.h: no ids, spawn slots as flags).
// 3: each client record keeps the participant that owns it (the binding of client ids).
// 2: the interest settings hashed apart from the rest of the config, and the match and snapshot
// sections length-prefixed (a reader can skip the baselines). 1: still restored (same config only).
// Versions 1 and 2 restore with owners of all zeros, which is what the inputs logged with them carry.
// 5: the connected clients only, after the next client id (a departed client's record is gone
// with it: client_registry.h). Versions 1 to 4 hold every client ever seen; restoring them keeps
// the connected ones.
constexpr std::uint32_t kVersion = 5;
constexpr std::uint32_t kOldestVersion = 1;
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
  // What the client's NPC gets back when the client goes (release) and the camera interest uses:
  // valid parameter values and a camera within the coordinates snapshots serve (kMaxCoordinateM),
  // as a live match only ever stores. Found by fuzzing: a character type of 1.002 was accepted and
  // the next timeout threw from set_param; a camera at -1.5e266 m made the next snapshot throw.
  const std::pair<params::Param, double> kept[] = {{params::Param::character_type, c.npc_character_type},
                                                   {params::Param::importance, c.npc_importance},
                                                   {params::Param::weight_kg, c.base_weight_kg}};
  for (const auto& [param, value] : kept) {
    if (const auto why = params::check_param_value(param, value)) {
      r.fail("client " + std::to_string(c.id) + ": " + std::string(params::param_name(param)) + " " + *why);
    }
  }
  if (!(std::fabs(c.camera.x) <= detail::kMaxCoordinateM) || !(std::fabs(c.camera.y) <= detail::kMaxCoordinateM) ||
      !(std::fabs(c.camera.z) <= detail::kMaxCoordinateM)) {
    r.fail("client " + std::to_string(c.id) + ": camera is not a finite coordinate within 1e6 m");
  }
  return c;
}

constexpr std::uint64_t kFnvBasis = 14695981039346656037ull;

// The config as checkpoints check it. sim: every field that changes the simulation state (not
// worker_threads or solver_threads: results do not depend on them, by design; not the interest settings: they shape
// snapshot content only). interest: the interest settings. v1: version 1's single hash (sim, then
// the interest fields mixed into the same stream).
struct ConfigHashes {
  std::uint64_t sim = 0, interest = 0, v1 = 0;
};

ConfigHashes config_hashes(const MatchConfig& config) {
  std::uint64_t c = kFnvBasis;
  c = mix(c, config.tick_hz); c = mix(c, config.max_clients); c = mix(c, config.client_timeout_s);
  c = mix(c, config.max_commands_per_tick); c = mix(c, config.player_speed_mps); c = mix(c, config.npc_speed_mps);
  c = mix(c, config.camera_limit_m); c = mix(c, config.seed);
  const auto mix_interest = [](std::uint64_t h, const InterestConfig& in) {
    h = mix(h, in.radius_m); h = mix(h, in.exit_hysteresis); h = mix(h, in.budget_bytes);
    h = mix(h, in.keepalive_ticks); h = mix(h, in.removed_repeat);
    return h;
  };
  return ConfigHashes{c, mix_interest(kFnvBasis, config.interest), mix_interest(c, config.interest)};
}

// The header and section boundaries (versions 1 to 3), read without decoding the sections.
struct Layout {
  std::uint32_t version = 0;
  std::uint64_t scene_hash = 0, config_hash = 0, interest_hash = 0;  // version 1: config_hash = ConfigHashes::v1
  std::uint32_t bodies = 0;
  std::uint64_t tick = 0;
  std::span<const std::uint8_t> world, match, snapshots;  // version 1: match runs to the end, snapshots empty
};

Layout read_layout(ByteReader& r) {
  Layout l;
  const auto magic = r.get<std::uint32_t>("magic");
  if (magic != kMagic) r.fail("not a match checkpoint (magic " + hex(magic) + ", expected " + hex(kMagic) + ")");
  l.version = r.get<std::uint32_t>("version");
  if (l.version < kOldestVersion || l.version > kVersion) {
    r.fail("checkpoint version " + std::to_string(l.version) + ", this build reads versions " +
           std::to_string(kOldestVersion) + " to " + std::to_string(kVersion));
  }
  l.scene_hash = r.get<std::uint64_t>("scene hash");
  l.config_hash = r.get<std::uint64_t>("config hash");
  if (l.version >= 2) l.interest_hash = r.get<std::uint64_t>("interest settings hash");
  l.bodies = r.get<std::uint32_t>("body count");
  l.tick = r.get<std::uint64_t>("tick");
  const auto section = [&r](const char* what) {
    const std::uint32_t len = r.get<std::uint32_t>(what);
    return std::span<const std::uint8_t>(r.take(len, what), len);
  };
  l.world = section("world section");
  if (l.version >= 2) {
    l.match = section("match section");
    l.snapshots = section("snapshot section");
    if (r.remaining() != 0) r.fail(std::to_string(r.remaining()) + " bytes after the end of the checkpoint");
  } else {
    l.match = std::span<const std::uint8_t>(r.take(r.remaining(), "match section"), r.remaining());
  }
  return l;
}

}  // namespace

CheckpointSections checkpoint_sections(std::span<const std::uint8_t> bytes) {
  ByteReader r(bytes);
  const Layout l = read_layout(r);
  return CheckpointSections{l.version, l.tick, l.world, l.match, l.snapshots};
}

void Match::Impl::compute_checkpoint_hashes() {
  // Scene: the table and initial policy (as MatchInfo hashes them), the scene name, the scenery
  // count and the world's state hash at construction, which covers every body's id, spawn pose,
  // size and initial push coefficients.
  std::uint64_t h = kFnvBasis;
  h = mix(h, info.param_table_hash);
  h = mix(h, info.push_policy_hash);
  h = fnv1a64(scene.name, h);
  h = mix(h, static_cast<std::uint64_t>(info.scenery.size()));
  h = mix(h, static_cast<std::uint64_t>(world().body_count()));
  h = mix(h, world().state_hash());
  scene_hash = h;
  // Config: every field that changes the simulation state (config_hashes above).
  config_hash = config_hashes(config).sim;
}

void Match::Impl::save_checkpoint(std::vector<std::uint8_t>& out, SaveOptions options) const {
  const std::uint32_t version = options.format_version == 0 ? kVersion : options.format_version;
  if (version != kVersion && version != 4 && version != 3) {
    throw std::invalid_argument("save_checkpoint: format_version " + std::to_string(options.format_version) +
                                ", this build writes 3 and " + std::to_string(kVersion));
  }
  ByteWriter w(out, ByteWriter::kOverwrite);  // = cleared first, without re-zeroing the bytes
  w.put(kMagic);
  w.put(version);
  w.put(scene_hash);
  w.put(config_hash);
  w.put(config_hashes(config).interest);
  w.put(static_cast<std::uint32_t>(world().body_count()));
  w.put(ticks);
  // Three length-prefixed sections, so a reader can skip one or hand the world to
  // diff_world_states: the world, the match state, the snapshot baselines.
  std::size_t len_at = w.size();
  const auto close_section = [&w, &len_at] { w.patch_u32(len_at, static_cast<std::uint32_t>(w.size() - len_at - 4)); };
  w.put(std::uint32_t{0});
  world().save_state(w);
  close_section();

  len_at = w.size();
  w.put(std::uint32_t{0});
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
  // Between ticks the registry holds exactly the connected clients. Versions 3 and 4 list every id
  // ever given out: the departed ones are written as records of nobody (not connected, no entity).
  // Visits the saved records in id order without allocating (a warm save allocates nothing).
  const auto for_each_saved = [this, version](auto&& visit) {
    if (version >= 5) {
      for (const auto& [id, c] : clients.records()) visit(c);
      return;
    }
    ClientRecord departed;
    for (std::uint32_t id = 1; id < clients.next_id(); ++id) {
      const ClientRecord* c = clients.find(id);
      departed.id = id;
      visit(c != nullptr ? *c : departed);
    }
  };
  const auto saved_count =
      static_cast<std::uint32_t>(version >= 5 ? clients.records().size() : clients.next_id() - 1);
  if (version >= 5) w.put(clients.next_id());
  w.put(saved_count);
  for_each_saved([&w](const ClientRecord& c) { put_client(w, c); });
  ai.save_state(w, version >= 4 ? NpcAi::AiStateForm::compact : NpcAi::AiStateForm::with_ids);
  // Version 3's trailer: each client's owner, then the client count again (so the section still
  // reads as version 2's up to here).
  for_each_saved([&w](const ClientRecord& c) {
    for (std::uint8_t b : c.owner.bytes) w.put(b);
  });
  w.put(saved_count);
  close_section();

  len_at = w.size();
  w.put(std::uint32_t{0});
  if (options.snapshot_baselines) snapshots.save_state(w);  // else empty: SnapshotBuilder::save_state never is
  close_section();
  w.finish();
}

namespace {

// Restores into m (Match::Impl; a template so that this file-local function may take the private
// type). Decodes everything into staging copies first, then restores the world (which checks and
// only then commits), then commits the rest: a bad checkpoint leaves the match unchanged.
template <class Impl>
void restore_match(Impl& m, std::span<const std::uint8_t> bytes, RestoreOptions options) {
  ByteReader header(bytes);
  const Layout l = read_layout(header);
  // A checkpoint saved without baselines (an empty snapshot section) restores as with reset.
  const bool saved_baselines = l.version == 1 || !l.snapshots.empty();
  const bool keep_baselines = options.snapshot_baselines == SnapshotBaselines::restore && saved_baselines;
  const std::size_t my_n = m.world().body_count();
  if (l.bodies != my_n) {
    throw CheckpointError("checkpoint is from another scene: it has " + std::to_string(l.bodies) + " bodies, this match " +
                          std::to_string(my_n));
  }
  if (l.scene_hash != m.scene_hash) {
    throw CheckpointError("checkpoint is from another scene: scene hash " + hex(l.scene_hash) + ", this match " +
                          hex(m.scene_hash) + " (parameter table, policy, scenery or spawn layout differ)");
  }
  const ConfigHashes mine = config_hashes(m.config);
  if (l.version == 1 ? l.config_hash != mine.v1 : l.config_hash != mine.sim) {
    throw CheckpointError("checkpoint is from a match with another config: config hash " + hex(l.config_hash) +
                          ", this match " + hex(l.version == 1 ? mine.v1 : mine.sim) +
                          (l.version == 1 ? " (a version 1 checkpoint includes the interest settings in it)" : ""));
  }
  if (l.version >= 2 && keep_baselines && l.interest_hash != mine.interest) {
    throw CheckpointError("checkpoint is from a match with another config: interest settings hash " + hex(l.interest_hash) +
                          ", this match " + hex(mine.interest) +
                          " (its snapshot baselines restore only into the same interest settings)");
  }
  const std::uint32_t n = l.bodies;
  ByteReader r(l.match);

  // Decode the match section into staging copies first: nothing changes until all of it decoded.
  const bool their_shutdown = r.get_bool("shutdown flag");
  const bool their_info_dirty = r.get_bool("match info dirty");
  std::vector<std::uint64_t> their_rejected;
  // foreign_participant, the last reason, came with version 3.
  r.get_array_exact(their_rejected, "reject counters", l.version >= 3 ? kRejectReasonCount : kRejectReasonCount - 1);
  their_rejected.resize(kRejectReasonCount, 0);
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
  r.get_array_exact(roster_faction, "roster factions", m.info.roster.faction.size());
  r.get_array_exact(roster_type, "roster character types", m.info.roster.character_type.size());
  std::vector<float> softness(r.get_count("scenery softness", m.info.scenery.size(), 4));
  if (softness.size() != m.info.scenery.size()) r.fail("scenery count differs from this match's");
  for (float& s : softness) s = r.get<float>("scenery softness");
  // Version 5: the next id, then the connected clients in ascending id order. Before: every client
  // ever seen, ids 1, 2, 3, ...; the next id follows the last.
  std::uint32_t next_id = 1;
  if (l.version >= 5) {
    next_id = r.get<std::uint32_t>("next client id");
    if (next_id == 0 || next_id > kMaxClientsEver + 1) r.fail("next client id " + std::to_string(next_id));
  }
  std::vector<ClientRecord> records;
  const std::uint32_t n_clients = r.get_count("clients", kMaxClientsEver, 100);
  for (std::size_t k = 0; k < n_clients; ++k) {
    records.push_back(get_client(r));
    const ClientRecord& c = records.back();
    if (l.version < 5) {
      if (c.id != k + 1) r.fail("client ids are not 1, 2, 3, ...");
    } else if (!c.connected) {
      r.fail("client " + std::to_string(c.id) + " is not connected (version 5 holds connected clients only)");
    } else if (c.id >= next_id || (k > 0 && c.id <= records[k - 1].id)) {
      r.fail("client ids are not ascending below the next client id " + std::to_string(next_id));
    }
  }
  if (l.version < 5) next_id = static_cast<std::uint32_t>(records.size()) + 1;
  for (std::uint32_t c : their_controller) {
    if (c >= next_id) r.fail("a body is controlled by client " + std::to_string(c) + ", never seen");
  }
  NpcAi staged_ai = m.ai;
  staged_ai.restore_state(r, n, l.version >= 4 ? NpcAi::AiStateForm::compact : NpcAi::AiStateForm::with_ids);
  if (l.version >= 3) {
    for (ClientRecord& c : records)
      for (std::uint8_t& b : c.owner.bytes) b = r.get<std::uint8_t>("client owner");
    if (r.get<std::uint32_t>("client owner count") != records.size()) r.fail("client owner count differs from the clients'");
  }
  SnapshotBuilder staged_snapshots(m.config.interest);
  // Version 1 has the snapshot section at the end of the match section.
  ByteReader snap = l.version == 1 ? r : ByteReader(l.snapshots);
  if (keep_baselines) {
    // The builder's tables grow to at most 1.25x the largest object index, at least 1,024
    // (interest_grid.cpp): anything beyond twice that is corrupt.
    staged_snapshots.restore_state(snap, std::max<std::size_t>(1024, 2 * m.body_slots));
    if (snap.remaining() != 0) snap.fail(std::to_string(snap.remaining()) + " bytes after the end of the checkpoint");
    // The builder serves exactly the connected clients (found by fuzzing: a connected client without
    // baselines made the next tick throw from SnapshotBuilder::build).
    std::uint32_t connected = 0;
    for (const ClientRecord& c : records) {
      if (!c.connected) continue;
      ++connected;
      if (!staged_snapshots.has_client(c.id)) snap.fail("connected client " + std::to_string(c.id) + " has no snapshot baselines");
    }
    if (staged_snapshots.client_count() != connected) snap.fail("snapshot baselines of clients that are not connected");
  } else {
    // As at each client's join (take_over): the builder knows exactly the connected clients.
    for (const ClientRecord& c : records) {
      if (c.connected) staged_snapshots.add_client(c.id, SnapshotBuilder::Residency::kLazy);  // a seek's restore
    }
  }
  if (l.version >= 2 && r.remaining() != 0) r.fail(std::to_string(r.remaining()) + " bytes after the match section");
  // Only the connected clients stay (versions 1 to 4 hold the departed ones too).
  std::erase_if(records, [](const ClientRecord& c) { return !c.connected; });
  // The record of a client id, by binary search (ids ascend); nullptr for one not connected.
  const auto connected_record = [&records](std::uint32_t id) -> const ClientRecord* {
    auto it = std::lower_bound(records.begin(), records.end(), id, [](const ClientRecord& c, std::uint32_t v) { return c.id < v; });
    return it != records.end() && it->id == id ? &*it : nullptr;
  };

  // Throws before changing anything (the AI's bodies checked against the decoded world section
  // first); the last thing that may throw.
  m.world().restore_state(l.world, [&](std::span<const ObjectId> ids) {
    staged_ai.bind_bodies(ids);
    // Clients and the bodies they control agree (found by fuzzing: a connected client whose entity
    // the world does not hold made the next snapshot read outside the position arrays).
    std::vector<std::uint32_t> controls(records.size(), 0);  // connected client (records' order) -> bodies controlled
    for (std::size_t d = 0; d < ids.size(); ++d) {
      const std::uint32_t c = their_controller[d];
      if (c == 0) continue;
      const ClientRecord* rec = connected_record(c);
      if (rec == nullptr || rec->entity != ids[d]) {
        throw CheckpointError("checkpoint: body " + std::to_string(ids[d].value) + " is controlled by client " +
                              std::to_string(c) + ", which does not control it");
      }
      ++controls[static_cast<std::size_t>(rec - records.data())];
    }
    for (const ClientRecord& rec : records) {
      if (controls[static_cast<std::size_t>(&rec - records.data())] != 1) {
        throw CheckpointError("checkpoint: connected client " + std::to_string(rec.id) + " does not control its entity " +
                              std::to_string(rec.entity.value));
      }
    }
  });

  // Commit.
  m.ticks = l.tick;
  m.shutting_down = their_shutdown;
  m.info_dirty = their_info_dirty;
  std::copy(their_rejected.begin(), their_rejected.end(), m.rejected.begin());
  m.accepted_total = their_accepted;
  m.yaw = std::move(their_yaw);
  m.controller = std::move(their_controller);
  m.info.state = static_cast<protocol::MatchState>(state);
  m.info.param_version = param_version;
  m.info.push_policy_hash = policy_hash_now;
  m.info.roster.faction = std::move(roster_faction);
  m.info.roster.character_type = std::move(roster_type);
  for (std::size_t s = 0; s < softness.size(); ++s) m.info.scenery[s].softness = softness[s];
  m.clients.restore(next_id, std::move(records));
  m.ai = std::move(staged_ai);
  m.snapshots = std::move(staged_snapshots);
  const World& w = m.world();
  for (std::size_t d = 0; d < n; ++d) m.id_values[d] = w.id_at(d).value;
  // The AI's arrays are in the order it saved them, the match's in the world's.
  m.ai.align_with(w);
  m.report = TickReport{};
}

}  // namespace

void Match::restore_checkpoint(std::span<const std::uint8_t> bytes, RestoreOptions options) {
  restore_match(*impl_, bytes, options);
  impl_->contacts_granted.clear();  // not in checkpoints: served again from the client's next command
}

}  // namespace throng::match
