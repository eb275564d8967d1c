// NpcAi checkpoints. Saved: the tick count (target-refresh phase), per body in dense order the id,
// group, faction slot, formation slot and charged enemy, every group (anchor, last centroid,
// own morale level = hysteresis state, ...), and the faction slots in order of appearance.
// Derived on restore: group_by_key_, faction_slot_, enemy_slots_ (from groups_ / slot_faction_),
// sum_x_/sum_y_ sizes. Not saved (scratch, rebuilt by every update() before it is read):
// body_cell_, the grid (start_, cursor_, ex_/ey_/ei_, near_, enemy_near_, window_ and its
// dimensions) and the align_with scratch.
#include <algorithm>
#include <string>
#include <vector>

#include "npc_ai.h"
#include "throng/core/byte_io.h"
#include "throng/params/object_params.h"

namespace throng::match {

void NpcAi::save_state(ByteWriter& w) const {
  w.put(ticks_);
  w.put_array(ids_);
  w.put_array(group_);
  w.put_array(fslot_);
  w.put_array(slot_x_);
  w.put_array(slot_y_);
  w.put_array(target_);
  w.put(static_cast<std::uint32_t>(groups_.size()));
  for (const AiGroup& g : groups_) {
    w.put(g.faction);
    w.put(g.group_id);
    w.put(g.faction_slot);
    w.put(g.anchor_x);
    w.put(g.anchor_y);
    w.put(g.centroid_x);
    w.put(g.centroid_y);
    w.put(g.members);
    w.put(g.npcs);
    w.put(g.target_group);
    w.put(static_cast<std::uint8_t>(g.own_morale));
    w.put(g.allies_near);
    w.put(g.enemies_near);
    w.put(g.morale);
    w.put(static_cast<std::uint8_t>(g.retreating ? 1 : 0));
  }
  w.put_array(slot_faction_);
}

void NpcAi::restore_state(ByteReader& r, std::size_t n) {
  ticks_ = r.get<std::uint64_t>("ai ticks");
  r.get_array_exact(ids_, "ai ids", n);
  r.get_array_exact(group_, "ai groups", n);
  r.get_array_exact(fslot_, "ai faction slots", n);
  r.get_array_exact(slot_x_, "ai slot x", n);
  r.get_array_exact(slot_y_, "ai slot y", n);
  r.get_array_exact(target_, "ai targets", n);
  groups_.resize(r.get_count("ai group count", 1u << 20, 60));
  for (AiGroup& g : groups_) {
    g.faction = r.get<std::uint8_t>("ai group");
    g.group_id = r.get<std::uint32_t>("ai group");
    g.faction_slot = r.get<std::uint32_t>("ai group");
    g.anchor_x = r.get<double>("ai group");
    g.anchor_y = r.get<double>("ai group");
    g.centroid_x = r.get<double>("ai group");
    g.centroid_y = r.get<double>("ai group");
    g.members = r.get<std::uint32_t>("ai group");
    g.npcs = r.get<std::uint32_t>("ai group");
    g.target_group = r.get<std::int32_t>("ai group");
    const auto morale = r.get<std::uint8_t>("ai group");
    if (morale > 2) r.fail("ai group morale level " + std::to_string(morale));
    g.own_morale = static_cast<params::MoraleState>(morale);
    g.allies_near = r.get<std::uint32_t>("ai group");
    g.enemies_near = r.get<std::uint32_t>("ai group");
    g.morale = r.get<double>("ai group");
    g.retreating = r.get_bool("ai group");
  }
  r.get_array(slot_faction_, "ai faction slots", 256);

  // Everything update() indexes with must be in range.
  const std::size_t ng = groups_.size(), nslots = slot_faction_.size();
  std::fill(std::begin(faction_slot_), std::end(faction_slot_), std::uint16_t{0xFFFF});
  for (std::size_t s = 0; s < nslots; ++s) {
    if (faction_slot_[slot_faction_[s]] != 0xFFFF) r.fail("ai faction listed twice");
    faction_slot_[slot_faction_[s]] = static_cast<std::uint16_t>(s);
  }
  group_by_key_.clear();
  for (std::size_t g = 0; g < ng; ++g) {
    const AiGroup& G = groups_[g];
    if (G.faction_slot >= nslots || slot_faction_[G.faction_slot] != G.faction) r.fail("ai group has a bad faction slot");
    if (G.target_group >= static_cast<std::int64_t>(ng)) r.fail("ai group targets a missing group");
    if (!group_by_key_.emplace(std::make_pair(G.faction, G.group_id), static_cast<std::uint32_t>(g)).second) {
      r.fail("ai group listed twice");
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (group_[i] >= ng || fslot_[i] >= nslots) r.fail("ai body " + std::to_string(i) + " has a bad group");
    if (target_[i] != 0xFFFFFFFFu && target_[i] >= n) r.fail("ai body " + std::to_string(i) + " targets a missing body");
  }
  rebuild_enemy_slots();
  sum_x_.assign(ng, 0.0);
  sum_y_.assign(ng, 0.0);
  body_cell_.resize(n);
  ex_.resize(n);
  ey_.resize(n);
  ei_.resize(n);
}

// Found by fuzzing (tests/fuzz match_checkpoint): a checkpoint whose AI named a body the world
// section does not hold was accepted, and the next tick threw from World::set_desired_velocity.
void NpcAi::check_bodies(std::span<const ObjectId> body_ids) const {
  bool same = ids_.size() == body_ids.size();
  if (same) {
    std::vector<std::uint32_t> mine(ids_.size()), theirs(body_ids.size());
    for (std::size_t i = 0; i < ids_.size(); ++i) {
      mine[i] = ids_[i].value;
      theirs[i] = body_ids[i].value;
    }
    std::sort(mine.begin(), mine.end());
    std::sort(theirs.begin(), theirs.end());
    same = mine == theirs;
  }
  if (!same) throw CheckpointError("checkpoint's NPC AI drives other bodies than its world section holds");
}

}  // namespace throng::match
