#pragma once
// The NPCs' brain: formations that march on the nearest enemy formation, soldiers that press into
// the nearest enemy once one is close, and formations that fall back when their morale breaks.
//
// Per tick, O(N) and allocation-free once the buffers have grown to the match's size:
//  1. group centroids (a group = the bodies sharing (faction, group_id); players count as members
//     for the centroid but are never steered);
//  2. a coarse uniform grid of every body, keyed (faction slot, cell) and filled by a counting sort
//     in dense order (deterministic), plus per faction a dilated "an enemy may be within the
//     engagement radius of this cell" flag (two sliding-window passes), so the rear ranks never
//     search;
//  3. per group: the nearest enemy group (by centroid), the morale, and the anchor: it advances
//     towards the enemy group's centroid at the NPC speed, or away from it while the group
//     retreats, but never runs more than a leash ahead of the group's own centroid;
//  4. per NPC: within the engagement radius of an enemy it heads for that enemy at full speed —
//     that is what makes the crowds press; else it steers to its formation slot (its spawn offset
//     from the group's spawn centroid) around the anchor, slowing down as it arrives. Retreating
//     groups do not engage. Yaw follows the desired velocity (polynomial atan2, ~1e-5 rad); a body
//     nearly at rest keeps its yaw.
//     The nearest enemy (ring search in the grid, nearest ring first, early exit) is re-chosen
//     every kTargetRefreshTicks ticks per NPC, staggered by dense index; in between, the NPC
//     follows its chosen enemy's current position (dropped when it leaves the radius). That
//     keeps the search — the one costly part once the lines meet — at a quarter of the NPCs per
//     tick, and the choice is at most 4 ticks old.
//
// Morale: the engine's group morale (base + level offset, GroupTable::morale) when the push policy
// reads morale (only then does the engine keep the level up to date); otherwise the same rule
// (params::update_morale with the table's thresholds and offsets) applied here to the allies and
// enemies within morale_radius_m of the group's centroid. A group whose morale is below
// retreat_below_morale retreats. So an operator (or a scene's table) lowering a group's base
// morale makes it fall back under any policy.
#include <cstdint>
#include <optional>
#include <map>
#include <span>
#include <utility>
#include <vector>

#include "throng/core/object_id.h"
#include "throng/params/morale.h"

namespace throng {
class World;
class ByteWriter;
class ByteReader;
}

namespace throng::match {

inline constexpr std::uint32_t kTargetRefreshTicks = 4;

struct NpcAiSettings {
  double speed_mps = 1.2;            // cruising and charging speed
  double dt_s = 1.0 / 30.0;          // tick length (anchor advance per tick = speed * dt)
  double engage_radius_m = 12.0;     // an NPC this close to an enemy goes for it
  double morale_radius_m = 10.0;     // allies/enemies counted around a group's centroid
  double retreat_below_morale = -10.0;  // group morale strictly below this: retreat
  double anchor_leash_m = 6.0;       // the anchor waits while it is this far from the centroid
  double arrive_gain_per_s = 1.5;    // speed towards the slot = min(speed, gain * distance)
  double arrive_tolerance_m = 0.05;  // closer than this to the slot: stand still
  double cell_m = 3.0;               // grid cell edge (grown automatically for huge worlds)
};

struct AiGroup {
  std::uint8_t faction = 0;
  std::uint32_t group_id = 0;
  std::uint32_t faction_slot = 0;
  double anchor_x = 0, anchor_y = 0;      // formation centre the NPCs steer around
  double centroid_x = 0, centroid_y = 0;  // of all members, this tick
  std::uint32_t members = 0;              // bodies (players included), this tick
  std::uint32_t npcs = 0;                 // of which AI-controlled
  std::int32_t target_group = -1;         // nearest enemy group, -1 = none
  params::MoraleState own_morale = params::MoraleState::normal;  // local-count level (see above)
  std::uint32_t allies_near = 0, enemies_near = 0;
  double morale = 0.0;                    // the value compared with retreat_below_morale
  bool retreating = false;
};

// The faction that is routed, if any: it still has groups with AI-controlled members and every
// one of them is retreating (its morale fell below retreat_below_morale while facing an enemy).
// Never the neutral faction; the lowest faction number when several are.
std::optional<std::uint8_t> routed_faction(std::span<const AiGroup> groups);

class NpcAi {
 public:
  explicit NpcAi(const NpcAiSettings& settings);

  // Reads every body's faction and group from the world; formation slots are the offsets from
  // each group's centroid now (call right after the scene is built: the spawn layout).
  void init(const World& world);
  // The body's faction or group_id changed (operator): it joins its new group, its slot being its
  // offset from that group's anchor now.
  void reassign(const World& world, std::size_t dense_index);

  // After a World::step that re-sorted the dense arrays: the AI's per-body arrays follow
  // (perm = World::last_reorder(), perm[new dense] = old dense).
  void apply_reorder(std::span<const std::uint32_t> perm);
  // After a restore: puts the AI's per-body arrays, saved in the order of the AI's own checkpoint,
  // into the world's dense order (by their ids). Returns whether the order changed.
  bool align_with(const World& world);

  // Desired velocities for every body with controlled[i] == 0 (dense order); yaw[i] is updated for
  // them. Returns the number of NPCs that went for an enemy this tick.
  std::uint32_t update(World& world, std::span<const std::uint32_t> controlled, std::span<float> yaw);

  // Checkpoints (npc_ai_state.cpp): the per-body brain (group, formation slot, charged enemy),
  // the groups (anchors, morale level, last centroids), the faction slots and the tick count.
  // The layout has two forms (`AiStateForm`): match checkpoints of version 4 and later hold `compact`,
  // older ones `with_ids`. restore_state replaces this AI's state (n bodies) or throws
  // CheckpointError part-way, so callers restore into a copy and move it in once everything else
  // has decoded too.
  enum class AiStateForm {
    // Per body its id and formation slot (x, y).
    with_ids,
    // No ids: the AI's order is the world's dense order (it follows every re-sort), so the world
    // section names the bodies. A formation slot still equal to the body's spawn slot (every NPC
    // no operator moved to another group) is a flag, not two doubles: the spawn layout is the
    // scene's, which the restoring match was built from.
    compact,
  };
  void save_state(ByteWriter& w, AiStateForm form) const;
  void restore_state(ByteReader& r, std::size_t n, AiStateForm form);
  // After restore_state: throws CheckpointError unless the restored AI drives exactly the bodies
  // `body_ids` (a world's, in its dense order; with `with_ids` the AI's own order may be an older
  // one, which align_with catches up with). With `compact` it takes those ids as its own and
  // resolves the spawn slots from them.
  void bind_bodies(std::span<const ObjectId> body_ids);

  std::span<const AiGroup> groups() const { return groups_; }
  std::uint32_t group_of(std::size_t dense_index) const { return group_[dense_index]; }
  const NpcAiSettings& settings() const { return settings_; }

 private:
  std::uint32_t slot_of_faction(std::uint8_t faction);
  std::uint32_t group_index(std::uint8_t faction, std::uint32_t group_id, double x, double y);
  void rebuild_enemy_slots();
  void compute_centroids(std::span<const double> xs, std::span<const double> ys, std::span<const std::uint32_t> controlled);
  void size_grid_for_max_cells();
  void build_grid(std::span<const double> xs, std::span<const double> ys);
  void dilate();
  void update_groups(const World& world);
  // Dense index of the nearest enemy within the engagement radius, or kNoTarget.
  std::uint32_t nearest_enemy(double x, double y, std::uint32_t fslot, std::uint32_t cell) const;
  std::uint32_t count_near(double x, double y, double r, std::uint32_t slot) const;

  NpcAiSettings settings_;
  // Per body (dense order).
  std::vector<ObjectId> ids_;
  std::vector<std::uint32_t> group_;
  std::vector<std::uint8_t> fslot_;
  std::vector<double> slot_x_, slot_y_;
  // The spawn layout by ObjectId index (init): the body's id value then (kNoSpawn if none) and its
  // slot. Scene data, never saved; the compact checkpoint refers to it.
  static constexpr std::uint32_t kNoSpawn = 0xFFFFFFFFu;
  std::vector<std::uint32_t> spawn_id_;
  std::vector<double> spawn_slot_x_, spawn_slot_y_;
  // Between restore_state(compact) and bind_bodies: which bodies keep their spawn slot.
  std::vector<std::uint8_t> restored_at_spawn_;
  bool restored_compact_ = false;
  void put_compact_slots(ByteWriter& w) const;
  std::vector<std::uint32_t> body_cell_;
  std::vector<std::uint32_t> target_;             // dense index of the enemy being charged, or kNoTarget
  std::uint64_t ticks_ = 0;
  std::vector<std::uint32_t> old_dense_of_slot_, perm_;  // scratch of align_with
  std::vector<ObjectId> scratch_ids_;
  std::vector<std::uint32_t> scratch_u32_;
  std::vector<std::uint8_t> scratch_u8_;
  std::vector<double> scratch_f64_;
  // Groups and faction slots.
  std::vector<AiGroup> groups_;
  std::map<std::pair<std::uint8_t, std::uint32_t>, std::uint32_t> group_by_key_;
  std::vector<std::uint8_t> slot_faction_;               // slot -> faction
  std::uint16_t faction_slot_[256];                      // faction -> slot, 0xFFFF = none
  std::vector<std::vector<std::uint32_t>> enemy_slots_;  // slot -> enemy slots
  std::vector<double> sum_x_, sum_y_;
  // Grid.
  double min_x_ = 0, min_y_ = 0, cell_m_ = 3.0, inv_cell_ = 1.0 / 3.0;
  std::uint32_t nx_ = 1, ny_ = 1, ncells_ = 1, rings_ = 1;
  std::vector<std::uint32_t> start_;  // (slot * ncells + cell) -> first entry; size nslots*ncells + 1
  std::vector<std::uint32_t> cursor_;
  std::vector<double> ex_, ey_;       // entries sorted by key
  std::vector<std::uint32_t> ei_;     // their dense indices
  std::vector<std::uint32_t> window_;  // dilation scratch
  std::vector<std::uint8_t> near_;     // (slot * ncells + cell): a body of that slot within `rings_` cells
  std::vector<std::uint8_t> enemy_near_;  // (slot * ncells + cell): an enemy of that slot may be in range
};

}  // namespace throng::match
