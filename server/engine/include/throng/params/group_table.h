#pragma once
// Groups (units, squads) that objects belong to, and their attributes from the patent's table:
// importance, member count, strength, and morale (the dynamic one).
//
// Dense table indexed by group id (1..kMaxGroupId, 0 = "no group") because the push policy reads a
// group's morale once per contact pair when the policy has a morale term; a vector index is the
// cheapest lookup and has no iteration-order question.
#include <cstdint>
#include <string>
#include <vector>

#include "throng/params/morale.h"
#include "throng/params/object_params.h"

namespace throng::params {

struct Group {
  double base_morale = 0.0;  // [-100, 100]; 0 = neutral. The policy reads base + level offset.
  MoraleState morale_state = MoraleState::normal;  // dynamic, advanced by update_morale
  std::uint32_t member_count = 0;  // [0, 1e6]
  double strength = 1.0;           // [0, 1e6], designer's unit strength
  double importance = 0.0;         // [0, 10]
};

// Throws ConfigError naming "<path>.<field>" for a value out of range or not finite.
void validate_group(const Group& g, const std::string& path);

class GroupTable {
 public:
  GroupTable() = default;
  explicit GroupTable(const MoraleConfig& config) { set_morale_config(config); }

  const MoraleConfig& morale_config() const { return config_; }
  void set_morale_config(const MoraleConfig& config);  // validates

  // Adds or replaces a group. id in [1, kMaxGroupId]. Throws ConfigError ("groups.<id>...").
  void set(std::uint32_t id, const Group& g);
  bool contains(std::uint32_t id) const { return find(id) != nullptr; }
  const Group* find(std::uint32_t id) const {
    return id < present_.size() && present_[id] != 0 ? &groups_[id] : nullptr;
  }
  // Throws std::out_of_range for an unknown id.
  const Group& at(std::uint32_t id) const;

  // Validated single-field updates for the runtime API.
  void set_base_morale(std::uint32_t id, double morale);
  void set_member_count(std::uint32_t id, std::uint32_t count);

  // Advances the group's morale level from the nearby counts (see morale.h) and returns it.
  MoraleState update_morale(std::uint32_t id, std::uint32_t allies_near, std::uint32_t enemies_near);

  // The morale value the policy uses: base + level offset. Objects without a (known) group read 0,
  // i.e. neutral morale, so a missing group neither helps nor hurts.
  double morale(std::uint32_t id) const {
    const Group* g = find(id);
    return g == nullptr ? 0.0 : g->base_morale + config_.offset(g->morale_state);
  }

  // Group ids in ascending order.
  std::vector<std::uint32_t> ids() const;
  std::size_t size() const { return count_; }

 private:
  Group& mutable_at(std::uint32_t id);

  MoraleConfig config_;
  std::vector<Group> groups_;
  std::vector<std::uint8_t> present_;
  std::size_t count_ = 0;
};

}  // namespace throng::params
