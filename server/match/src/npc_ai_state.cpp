// NpcAi checkpoints. Saved: the tick count (target-refresh phase), per body in dense order the
// group, faction slot, formation slot and charged enemy, every group (anchor, last centroid,
// own morale level = hysteresis state, ...), and the faction slots in order of appearance.
// Written in the compact form (npc_ai.h, AiStateForm): no ids, and a formation slot equal to the
// body's spawn slot as a flag. Why: the ids repeat the world section's, and the slots are two
// doubles per body that almost never change after spawn; together they were a sixth of a battle
// keyframe after compression.
// Derived on restore: the ids (compact: the world's dense order), group_by_key_, faction_slot_,
// enemy_slots_ (from groups_ / slot_faction_), sum_x_/sum_y_ sizes. Not saved (scratch, rebuilt by
// every update() before it is read): body_cell_, the grid (start_, cursor_, ex_/ey_/ei_, near_,
// enemy_near_, window_ and its dimensions) and the align_with scratch. Not saved either: the spawn
// layout (scene data, the same in every match built from the scene).
#include <algorithm>
#include <bit>
#include <string>
#include <vector>

#include "npc_ai.h"
#include "throng/core/byte_io.h"
#include "throng/params/object_params.h"

namespace throng::match {

namespace {

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

}  // namespace

void NpcAi::save_state(ByteWriter& w, AiStateForm form) const {
  w.put(ticks_);
  if (form == AiStateForm::with_ids) {
    w.put_array(ids_);
    w.put_array(group_);
    w.put_array(fslot_);
    w.put_array(slot_x_);
    w.put_array(slot_y_);
  } else {
    w.put_array(group_);
    w.put_array(fslot_);
    put_compact_slots(w);
  }
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

// Formation slots, compact: a flag per body (1 = its spawn slot), then x and y of the others.
void NpcAi::put_compact_slots(ByteWriter& w) const {
  const std::size_t n = ids_.size();
  const auto at_spawn = [this](std::size_t i) {
    const std::uint32_t k = ids_[i].index();
    return k < spawn_id_.size() && spawn_id_[k] == ids_[i].value && same_bits(slot_x_[i], spawn_slot_x_[k]) &&
           same_bits(slot_y_[i], spawn_slot_y_[k]);
  };
  std::uint32_t moved = 0;
  w.put(static_cast<std::uint32_t>(n));
  std::uint8_t* flag = w.grow(n);
  for (std::size_t i = 0; i < n; ++i) {
    flag[i] = at_spawn(i) ? 1 : 0;
    moved += flag[i] == 0 ? 1u : 0u;
  }
  for (const std::vector<double>* col : {&slot_x_, &slot_y_}) {
    w.put(moved);
    for (std::size_t i = 0; i < n; ++i) {
      if (!at_spawn(i)) w.put((*col)[i]);
    }
  }
}

void NpcAi::restore_state(ByteReader& r, std::size_t n, AiStateForm form) {
  ticks_ = r.get<std::uint64_t>("ai ticks");
  restored_compact_ = form == AiStateForm::compact;
  if (!restored_compact_) r.get_array_exact(ids_, "ai ids", n);
  r.get_array_exact(group_, "ai groups", n);
  r.get_array_exact(fslot_, "ai faction slots", n);
  if (restored_compact_) {
    r.get_array_exact(restored_at_spawn_, "ai slot at spawn", n);
    std::size_t moved = 0;
    for (std::uint8_t f : restored_at_spawn_) {
      if (f > 1) r.fail("ai slot flag " + std::to_string(f));
      moved += f == 0 ? 1 : 0;
    }
    // The moved bodies' slots, in dense order; bind_bodies puts the spawn slots between them.
    r.get_array_exact(slot_x_, "ai slot x", moved);
    r.get_array_exact(slot_y_, "ai slot y", moved);
    ids_.clear();
  } else {
    r.get_array_exact(slot_x_, "ai slot x", n);
    r.get_array_exact(slot_y_, "ai slot y", n);
  }
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
void NpcAi::bind_bodies(std::span<const ObjectId> body_ids) {
  if (restored_compact_) {
    const std::size_t n = restored_at_spawn_.size();
    if (body_ids.size() != n) throw CheckpointError("checkpoint's NPC AI drives other bodies than its world section holds");
    ids_.assign(body_ids.begin(), body_ids.end());
    std::vector<double> xs(n), ys(n);
    std::size_t next = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (restored_at_spawn_[i] == 0) {
        xs[i] = slot_x_[next];
        ys[i] = slot_y_[next];
        ++next;
        continue;
      }
      const std::uint32_t k = ids_[i].index();
      if (k >= spawn_id_.size() || spawn_id_[k] != ids_[i].value) {
        throw CheckpointError("checkpoint's NPC AI keeps the spawn slot of body " + std::to_string(ids_[i].value) +
                              ", which the scene did not spawn");
      }
      xs[i] = spawn_slot_x_[k];
      ys[i] = spawn_slot_y_[k];
    }
    slot_x_ = std::move(xs);
    slot_y_ = std::move(ys);
    restored_at_spawn_.clear();
    restored_compact_ = false;
    return;
  }
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
