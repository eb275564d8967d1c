// Behavior names -> factories, and the --behavior spec ("wander", "nan,flood", "mix").
#include <stdexcept>
#include <string>

#include "steer.h"

namespace throng::client_sim {

namespace {
struct Entry {
  const char* name;
  std::unique_ptr<Behavior> (*make)();
  bool misbehavior;
};
constexpr Entry kRegistry[] = {
    {"wander", detail::make_wander, false}, {"charge", detail::make_charge, false},
    {"waypoints", detail::make_waypoints, false}, {"idle", detail::make_idle, false},
    {"nan", detail::make_nan, true},       {"flood", detail::make_flood, true},
    {"hijack", detail::make_hijack, true}, {"stale", detail::make_stale, true},
};
const Entry* find(std::string_view name) {
  for (const Entry& e : kRegistry)
    if (name == e.name) return &e;
  return nullptr;
}
}  // namespace

std::unique_ptr<Behavior> make_behavior(std::string_view name) {
  const Entry* e = find(name);
  if (!e) throw std::invalid_argument("unknown behavior '" + std::string(name) + "'");
  return e->make();
}

const std::vector<std::string>& behavior_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const Entry& e : kRegistry) v.emplace_back(e.name);
    return v;
  }();
  return names;
}

bool is_misbehavior(std::string_view name) {
  const Entry* e = find(name);
  return e && e->misbehavior;
}

std::vector<std::string> expand_behavior_spec(std::string_view spec) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= spec.size()) {
    const std::size_t comma = spec.find(',', start);
    const std::string_view item = spec.substr(start, comma == std::string_view::npos ? spec.npos : comma - start);
    if (item == "mix") {
      for (const char* n : {"wander", "charge", "waypoints", "idle"}) out.emplace_back(n);
    } else if (find(item)) {
      out.emplace_back(item);
    } else {
      throw std::invalid_argument("unknown behavior '" + std::string(item) + "' (expected one of wander, charge, "
                                  "waypoints, idle, nan, flood, hijack, stale, mix, or a comma-separated list)");
    }
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace throng::client_sim
