#include "throng/params/group_table.h"

#include <cmath>
#include <stdexcept>

#include "text_util.h"
#include "throng/params/config_error.h"

namespace throng::params {
namespace {

void check_range(double v, double lo, double hi, const std::string& path) {
  if (std::isnan(v)) throw ConfigError(path, "NaN is not allowed");
  if (std::isinf(v)) throw ConfigError(path, "infinite value is not allowed");
  if (v < lo || v > hi) {
    throw ConfigError(path, detail::format_number(v) + " is out of range [" + detail::format_number(lo) + ", " +
                                detail::format_number(hi) + "]");
  }
}

std::string group_path(std::uint32_t id) { return "groups." + std::to_string(id); }

}  // namespace

void validate_group(const Group& g, const std::string& path) {
  check_range(g.base_morale, -100.0, 100.0, path + ".morale");
  check_range(static_cast<double>(g.member_count), 0.0, 1.0e6, path + ".member_count");
  check_range(g.strength, 0.0, 1.0e6, path + ".strength");
  check_range(g.importance, 0.0, 10.0, path + ".importance");
  if (static_cast<std::uint8_t>(g.morale_state) > static_cast<std::uint8_t>(MoraleState::high)) {
    throw ConfigError(path + ".morale_state", "unknown morale state");
  }
}

void GroupTable::set_morale_config(const MoraleConfig& config) {
  config.validate();
  config_ = config;
}

void GroupTable::set(std::uint32_t id, const Group& g) {
  if (id == 0 || id > kMaxGroupId) {
    throw ConfigError(group_path(id), "group id must be in [1, " + std::to_string(kMaxGroupId) + "]");
  }
  validate_group(g, group_path(id));
  if (id >= groups_.size()) {
    groups_.resize(std::size_t{id} + 1);
    present_.resize(std::size_t{id} + 1, 0);
  }
  if (present_[id] == 0) ++count_;
  present_[id] = 1;
  groups_[id] = g;
}

const Group& GroupTable::at(std::uint32_t id) const {
  const Group* g = find(id);
  if (g == nullptr) throw std::out_of_range("unknown group id " + std::to_string(id));
  return *g;
}

Group& GroupTable::mutable_at(std::uint32_t id) {
  if (find(id) == nullptr) throw std::out_of_range("unknown group id " + std::to_string(id));
  return groups_[id];
}

void GroupTable::set_base_morale(std::uint32_t id, double morale) {
  Group& g = mutable_at(id);
  check_range(morale, -100.0, 100.0, group_path(id) + ".morale");
  g.base_morale = morale;
}

void GroupTable::set_member_count(std::uint32_t id, std::uint32_t count) {
  Group& g = mutable_at(id);
  check_range(static_cast<double>(count), 0.0, 1.0e6, group_path(id) + ".member_count");
  g.member_count = count;
}

MoraleState GroupTable::update_morale(std::uint32_t id, std::uint32_t allies_near, std::uint32_t enemies_near) {
  Group& g = mutable_at(id);
  g.morale_state = params::update_morale(g.morale_state, allies_near, enemies_near, config_);
  return g.morale_state;
}

std::vector<std::uint32_t> GroupTable::ids() const {
  std::vector<std::uint32_t> out;
  out.reserve(count_);
  for (std::uint32_t id = 0; id < present_.size(); ++id) {
    if (present_[id] != 0) out.push_back(id);
  }
  return out;
}

}  // namespace throng::params
