#pragma once
// Match's private state, shared by the files that implement its phases:
//   match.cpp          construction, tick() and the read accessors
//   match_joins.cpp    joins, leaves, timeouts, entity takeover / hand-back
//   match_commands.cpp command validation order and application, cameras
//   param_updates.cpp  operator parameter / policy changes
//   match_snapshots.cpp one Snapshot per connected client
//   match_contacts.cpp  the contact-pairs debug channel (grants, one ContactPairs per granted client)
#include <array>
#include <cstdint>
#include <exception>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "client_registry.h"
#include "npc_ai.h"
#include "throng/core/worker_pool.h"
#include "throng/match/contacts.h"
#include "throng/match/input_queue.h"
#include "throng/match/match.h"
#include "throng/match/match_config.h"
#include "throng/match/snapshot_builder.h"
#include "throng/params/param_table.h"
#include "throng/protocol/messages.h"
#include "throng/scene/build_scene.h"
#include "throng/scene/scene_def.h"

namespace throng::match {

// Importance a player's entity gets when the parameter table has no "player" archetype.
inline constexpr double kDefaultPlayerImportance = 8.0;
// Sprinting multiplies the player's speed by this; bracing multiplies the entity's weight.
inline constexpr double kSprintFactor = 1.5;
inline constexpr double kBraceWeightFactor = 2.0;
inline constexpr std::size_t kMaxNameBytes = 64;
inline constexpr std::uint32_t kNoDense = 0xFFFFFFFFu;

struct Match::Impl {
  Impl(const scene::SceneDef& scene, const MatchConfig& config, std::string match_id);

  World& world() { return built.world; }
  const World& world() const { return built.world; }

  // --- phases (apply) -------------------------------------------------------------------------
  void apply_joins(std::uint64_t tick, Outbox& out);
  void apply_commands(std::uint64_t tick);
  void apply_params(std::uint64_t tick, Outbox& out);
  void apply_timeouts(std::uint64_t tick, Outbox& out);
  void feed_cameras();
  void build_snapshots(std::uint64_t tick, Outbox& out);
  void note_contacts_request(const ClientRecord& c, bool wants);  // per applied command
  void build_contacts(std::uint64_t tick, Outbox& out);

  // --- helpers ---------------------------------------------------------------------------------
  std::optional<RejectReason> check_command(const protocol::Command& c, std::uint64_t tick);
  protocol::ParamReply apply_param_update(const protocol::ParamUpdate& u, std::uint64_t tick);
  void handle_join(const protocol::JoinRequest& r, std::uint64_t tick, Outbox& out);
  void handle_leave(const protocol::JoinRequest& r, std::uint64_t tick, Outbox& out);
  std::optional<std::uint32_t> choose_entity(std::uint32_t client_id) const;  // dense index
  void take_over(ClientRecord& c, std::uint32_t dense, std::uint64_t tick);
  void release(ClientRecord& c);  // hands the entity back to the AI and disconnects the client
  protocol::JoinReply accepted_reply(const ClientRecord& c, std::uint64_t tick) const;
  void set_brace(ClientRecord& c, bool bracing);
  double braced_weight(double base_kg) const;
  Vec3 camera_of(const ClientRecord& c) const;
  std::uint32_t dense_of(ObjectId id) const;  // kNoDense for scenery / unknown
  // After World::step: the per-body arrays follow the world's re-sort, if it made one
  // (World::last_reorder).
  void follow_reorder();

  // --- checkpoints (match_checkpoint.cpp) ---------------------------------------------------------
  void save_checkpoint(std::vector<std::uint8_t>& out, SaveOptions options) const;
  void compute_checkpoint_hashes();

  MatchConfig config;
  std::string match_id;
  scene::SceneDef scene;  // as given, with settings.dt_s = 1 / tick_hz
  params::ParamTable table;
  scene::BuiltScene built;  // its SceneDriver is not used: NPCs are driven by the AI
  InputQueue queue;
  TickInputs inputs;
  ClientRegistry clients;
  NpcAi ai;
  SnapshotBuilder snapshots;
  // The snapshots phase runs on config.worker_threads threads (throng/core/worker_pool.h); one Scratch and
  // one partial-statistics slot per worker, reduced after the phase.
  WorkerPool pool;
  std::vector<SnapshotBuilder::Scratch> scratches;
  struct WorkerTotals {
    std::uint32_t poses = 0;
    double view_error_max_m = 0;
    std::exception_ptr error;
  };
  std::vector<WorkerTotals> worker_totals;
  SnapshotSink sink;
  protocol::MatchInfo info;
  TickReport report;
  std::array<std::uint64_t, kRejectReasonCount> rejected{};
  std::uint64_t accepted_total = 0;
  std::uint64_t ticks = 0;          // ticks simulated so far
  std::uint64_t timeout_ticks = 1;  // client_timeout_s * tick_hz, rounded
  double player_importance = kDefaultPlayerImportance;
  bool shutting_down = false;
  bool info_dirty = true;           // republish match_info at the next tick (first tick, shutdown)
  // What a checkpoint must have been taken from (set at construction, match_checkpoint.cpp).
  std::uint64_t scene_hash = 0;     // parameter table, initial policy, scene name, spawn layout
  std::uint64_t config_hash = 0;    // MatchConfig fields that change results

  // Per body, in the world's dense order, which the World re-sorts every few ticks
  // (follow_reorder keeps these in step). The match never creates or destroys bodies.
  std::vector<std::uint32_t> id_values;
  std::vector<float> yaw;
  std::vector<std::uint32_t> controller;      // client id, 0 = NPC
  std::vector<Vec3> cameras;                  // scratch for World::set_cameras
  std::vector<std::uint32_t> roster_of_slot;  // ObjectId::index() -> MatchInfo roster index
  std::size_t body_slots = 0;                 // 1 + the largest ObjectId::index() of the bodies
  std::vector<std::uint32_t> scratch_u32;
  std::vector<float> scratch_f32;

  // The contacts debug channel (match_contacts.cpp). Capacity reserved at construction.
  ContactSelector contact_selector;
  std::vector<std::uint32_t> contacts_granted;  // client ids served, ascending
  std::uint64_t contacts_refused = 0;
};

}  // namespace throng::match
