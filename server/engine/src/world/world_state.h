#pragma once
// A World's simulation state decoded from checkpoint bytes but not yet applied: restore_state
// decodes and checks everything into one of these first and only then moves it into the world
// (so a bad checkpoint leaves the world untouched), and diff_world_states compares two of them.
#include <cstdint>
#include <utility>
#include <vector>

#include "throng/core/byte_io.h"
#include "throng/core/vec3.h"
#include "throng/params/group_table.h"
#include "throng/params/object_params.h"
#include "throng/params/push_policy.h"
#include "world/body_store.h"

namespace throng::detail {

inline constexpr std::uint32_t kWorldStateMagic = 0x53574854;  // "THWS" in the file
// 4: the pair list's kept byte may say a search was begun (2); 3: no body id column (the slots'
// dense references name every body); 2: the kept pair list. This build reads 2 to 4.
inline constexpr std::uint32_t kWorldStateVersion = 4;
inline constexpr std::uint32_t kOldestWorldStateVersion = 2;

// Bounds of the pair list's cooldown (World::Impl::PairList), checked when a checkpoint is read.
inline constexpr std::uint32_t kPairListCooldownTicks = 8;
inline constexpr std::uint32_t kPairListMaxCooldownTicks = 256;

struct WorldState {
  std::uint64_t config_hash = 0;
  std::uint64_t tick = 0;
  std::uint32_t iterations = 0;
  std::vector<std::uint32_t> slot_generation;
  std::vector<std::uint8_t> slot_kind;  // World::Impl::SlotKind
  std::vector<std::uint32_t> slot_ref;
  std::vector<std::uint32_t> free_slots;
  std::vector<params::ObjectParams> fixed_params;
  bool scenery_dirty = false;
  double max_body_reach_m = 0.0, scenery_reach_m = 0.0;
  BodyStore bodies;  // warm entries beyond warm_count are zero
  std::vector<params::ObjectParams> body_params;
  std::vector<Vec3> cameras;
  bool all_coefficients_dirty = true;
  std::vector<std::pair<std::uint32_t, params::Group>> groups;
  bool morale_counts_present = false;
  std::vector<std::uint32_t> morale_allies, morale_enemies;  // full size when present
  std::uint64_t policy_version = 0;
  params::PushPolicy policy;
  // A kept pair list (World::Impl::PairList): where it was searched, dense order; empty if none.
  std::uint32_t pair_list_kept_ticks = 0, pair_list_cooldown = 0, pair_list_backoff = 0;
  bool pair_list_kept = false;
  bool pair_list_ahead_begun = false;  // version 4: the next list's search was begun (list.ahead_begun)
  std::vector<double> pair_list_x, pair_list_y, pair_list_z;
};

// Reads one world section (the magic through the policy) and checks that it is self-consistent:
// column lengths, slot kinds and references, ids that name their own slot. Throws CheckpointError.
WorldState decode_world_state(ByteReader& r);

}  // namespace throng::detail
