#pragma once
// One match: the world, the connected clients, the NPC AI and the snapshots, advanced one fixed
// tick at a time. No clocks, no threads, no DDS: tick() is a pure function of the scene, the
// config and the inputs drained so far, which is what makes logs replayable and tests exact.
// The server app (server/app) owns the real-time loop and the DDS transport around it.
//
// Tick phases, in order (TickReport times each):
//   drain     — take the queued inputs, sorted (input_queue.h)
//   apply     — joins/leaves, validated commands, operator parameter changes, client timeouts
//   ai        — desired velocities for every NPC
//   step      — World::step
//   snapshots — one Snapshot per client (snapshot_builder.h)
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "throng/core/byte_io.h"
#include "throng/match/input_queue.h"
#include "throng/match/match_config.h"
#include "throng/protocol/messages.h"
#include "throng/scene/scene_def.h"
#include "throng/world/step_stats.h"

namespace throng {
class World;
struct ObjectId;
}

namespace throng::match {

// A checkpoint that cannot be restored here: truncated or malformed bytes, another format version,
// or taken from a match with another scene or config (the message says which).
using CheckpointError = throng::CheckpointError;

// Why a command was rejected. Each rejected command changes nothing in the world.
enum class RejectReason : std::uint8_t {
  non_finite = 0,        // NaN/Inf in any float
  move_out_of_range,     // |move| > 1 (+1e-3 slack)
  facing_out_of_range,   // |facing| > pi (+1e-3 slack)
  camera_out_of_range,   // |camera coordinate| > camera_limit_m
  bad_actions,           // unknown action bits
  unknown_client,        // client id not connected
  not_your_entity,       // entity is not the one this client controls
  stale_sequence,        // sequence below the newest applied
  duplicate_sequence,    // sequence equal to one already applied
  rate_limited,          // more than max_commands_per_tick from one client in a tick
  foreign_participant,   // sent by another DDS participant than the one that joined the client
  count_
};
inline constexpr std::size_t kRejectReasonCount = static_cast<std::size_t>(RejectReason::count_);
const char* to_string(RejectReason r);

struct TickReport {
  std::uint64_t tick = 0;       // the tick just simulated
  std::uint64_t state_hash = 0; // World::state_hash after the step
  double drain_us = 0, apply_us = 0, ai_us = 0, step_us = 0, snapshots_us = 0, total_us = 0;
  std::uint32_t joins_accepted = 0, joins_refused = 0, leaves = 0, timeouts = 0;
  std::uint32_t joins_foreign = 0;  // joins/leaves naming another participant's client (not answered)
  std::uint32_t commands_accepted = 0, commands_rejected = 0;
  std::uint32_t param_updates_applied = 0, param_updates_rejected = 0;
  std::uint32_t push_events = 0;  // contacts pushed this tick
  std::uint32_t snapshot_poses = 0;
  double view_error_max_m = 0;    // over all clients this tick
  std::uint32_t contact_pairs = 0;     // pairs sent on the contacts channel this tick, all clients
  std::uint32_t contacts_refused = 0;  // commands asking for contacts the channel had no room for
  StepStats world;  // what the world's step did (phase times, searches, solver figures)
};

// Lifecycle events the transport must act on (open/close a client's snapshot channel) and the
// server logs. Filled by tick().
struct ClientEvent {
  enum class Kind : std::uint8_t { joined, left, timed_out } kind;
  std::uint32_t client_id = 0;
  std::uint32_t entity = 0;
  std::string partition;
  std::string name;
  // left / timed_out: the client's command totals at departure (the match forgets it after).
  std::uint64_t commands_accepted = 0;
  std::uint64_t commands_rejected = 0;
};

// Everything a tick produced for the network. Reused tick to tick (vectors keep capacity).
struct Outbox {
  std::vector<protocol::JoinReply> join_replies;
  std::vector<protocol::ParamReply> param_replies;
  std::vector<ClientEvent> client_events;
  std::vector<protocol::Snapshot> snapshots;  // first snapshot_count are this tick's
  std::size_t snapshot_count = 0;
  // The contacts debug channel: one per granted client, ascending client id; first
  // contacts_count are this tick's.
  std::vector<protocol::ContactPairs> contacts;
  std::size_t contacts_count = 0;
  bool match_info_changed = false;            // republish match_info()
  void clear() {
    join_replies.clear();
    param_replies.clear();
    client_events.clear();
    snapshot_count = 0;
    contacts_count = 0;
    match_info_changed = false;
  }
};

// What Match::restore_checkpoint does with the snapshot builder's per-client baselines (each
// client's copy of every object it was sent: what its next snapshots contain depends on them).
enum class SnapshotBaselines : std::uint8_t {
  // Restored: the checkpoint must come from a match with the same interest settings (checked), and
  // the next snapshots are byte for byte those the saved match would have built. A checkpoint
  // saved without baselines (SaveOptions) has none to restore: it restores as with reset.
  restore,
  // Not read: every connected client starts from an empty baseline, as a client that has just
  // joined, under this match's own interest settings, which may differ from the saved match's
  // (the interest settings and baselines shape snapshot content only; nothing the snapshots phase
  // computes feeds back into the world, the AI or the clients, so state hashes continue exactly as
  // in the saved match). For re-simulations that need the world and its hashes, not the saved
  // snapshot stream: verify, seeking for a viewer. Checkpoint version 2 or later (version 1 mixed
  // the interest settings into its config hash: it restores only into the same interest settings).
  reset,
};

struct RestoreOptions {
  SnapshotBaselines snapshot_baselines = SnapshotBaselines::restore;
};

struct SaveOptions {
  // false: the snapshot section is left empty. Such a checkpoint restores in either
  // SnapshotBaselines mode, into any interest settings, with every connected client starting from
  // an empty baseline (as with reset). Why: with many clients the baselines are most of a
  // checkpoint, and only a replay that must publish byte for byte what the server sent after a
  // seek needs them (match log keyframes leave them out unless asked to).
  bool snapshot_baselines = true;
  // The checkpoint version to write: 0 = this build's newest (5: connected clients only); 4 = the
  // one builds before it read (every client id ever given out, departed ones as empty records); 3 =
  // the one builds before the compact NPC AI read (every body's id and formation slot in the AI).
  // Anything else throws std::invalid_argument. Why: a log meant for the previous build, and the
  // tests that make the older versions earlier builds wrote.
  std::uint32_t format_version = 0;
};

// Where the sections of a checkpoint are (layout: server/match/src/CHECKPOINT.md), found from its
// header and section lengths without decoding them. Throws CheckpointError on bad bytes.
struct CheckpointSections {
  std::uint32_t version = 0;
  std::uint64_t tick = 0;
  std::span<const std::uint8_t> world;               // World::save_state bytes
  // Version 2: the match state between the world and the snapshot baselines (clients, NPC AI, ...),
  // and the snapshot builder's section. Version 1: everything after the world, baselines included,
  // in match_state (the baselines are not length-prefixed there); snapshot_baselines empty.
  std::span<const std::uint8_t> match_state;
  std::span<const std::uint8_t> snapshot_baselines;
};
CheckpointSections checkpoint_sections(std::span<const std::uint8_t> bytes);

struct ClientSummary {
  std::uint32_t client_id = 0;
  std::uint32_t entity = 0;
  std::string name;
  std::uint32_t last_applied_sequence = 0;
  std::uint64_t joined_tick = 0;
  std::uint64_t commands_accepted = 0;  // commands carrying this client_id, by outcome
  std::uint64_t commands_rejected = 0;  //   (unknown_client rejections belong to no client)
  std::string partition;                // the client's snapshot partition (JoinReply::snapshot_partition)
};

class Match {
 public:
  // Builds the scene's world. Throws scene::SceneError / std::invalid_argument on bad input.
  Match(const scene::SceneDef& scene, const MatchConfig& config, std::string match_id);
  ~Match();
  Match(const Match&) = delete;
  Match& operator=(const Match&) = delete;

  InputQueue& inputs();
  const InputQueue& inputs() const;

  // Called for each client's snapshot as soon as it is built, on the snapshot worker threads
  // (several at once: it must be thread-safe — the DDS transport is). Lets the server publish
  // while other snapshots are still being built. Snapshots are still left in the Outbox.
  using SnapshotSink = std::function<void(const protocol::Snapshot&)>;
  void set_snapshot_sink(SnapshotSink sink);

  // Runs one tick (the phases above) and fills out (out.clear() is called first).
  const TickReport& tick(Outbox& out);

  // From now on joins are refused with shutting_down. The final match info has state = ended.
  void begin_shutdown();

  const protocol::MatchInfo& match_info() const;
  // The inputs the last tick() drained, in the order it applied them (rejected ones included:
  // they are part of what happened, and re-applying them changes nothing). Feeding exactly these
  // to a fresh Match with the same scene and config, tick by tick, reproduces every state hash —
  // which is what the match log records and replay verifies.
  const TickInputs& last_inputs() const;
  std::uint64_t tick_index() const;         // ticks simulated so far
  std::uint64_t state_hash() const;
  std::uint32_t client_count() const;
  std::vector<ClientSummary> clients() const;
  std::uint32_t npc_count() const;
  // A side whose every AI group is retreating (npc_ai.h routed_faction), as of the last tick.
  std::optional<std::uint8_t> routed_faction() const;
  // Totals since the match started, by reason.
  const std::array<std::uint64_t, kRejectReasonCount>& rejected_by_reason() const;
  std::uint64_t commands_accepted_total() const;
  const MatchConfig& config() const;
  const World& world() const;
  // The facing of a body in radians (a client's from its commands, an NPC's from the AI), as
  // snapshots carry it; nullopt when id is not a body.
  std::optional<float> facing_rad(ObjectId id) const;

  // --- the contact-pairs debug channel (match_contacts.cpp) ------------------------------------
  // A client asks with kActionContacts in its commands; while its newest applied command carries
  // the bit (and it holds one of config.contacts.max_clients places, first come) the tick builds
  // it a ContactPairs in the Outbox. Requests the channel has no room for are refused (the command
  // itself still applies) and counted. Never changes the simulation. Not in checkpoints: after a
  // restore a client is served again from its next command.
  std::span<const std::uint32_t> contacts_clients() const;  // served now, ascending id
  std::uint64_t contacts_refused_total() const;

  // --- checkpoints (layout: server/match/src/CHECKPOINT.md) ------------------------------------
  // Writes the match's complete simulation state into `out` (cleared first; its capacity is
  // reused, so a warm buffer does not allocate). const: safe beside other const readers, not
  // during tick().
  void save_checkpoint(std::vector<std::uint8_t>& out) const;
  void save_checkpoint(std::vector<std::uint8_t>& out, SaveOptions options) const;
  // Replaces this match's simulation state with `bytes`, taken from a Match built from the same
  // scene and config. Afterwards tick() gives bit-identical results (state hashes, outbox,
  // snapshots) to the match the checkpoint was taken from. Throws CheckpointError for truncated or
  // malformed bytes, wrong magic/version, or a checkpoint of another scene/config; the match is
  // unchanged then. Inputs queued but not yet drained stay queued; the snapshot sink and the
  // match id are this match's own.
  void restore_checkpoint(std::span<const std::uint8_t> bytes);
  // The same with options (the one above is options = {}): snapshot_baselines = reset restores
  // everything but the snapshot baselines, also into a match whose interest settings differ from
  // the saved one's (see SnapshotBaselines); the next snapshots start afresh.
  void restore_checkpoint(std::span<const std::uint8_t> bytes, RestoreOptions options);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace throng::match
