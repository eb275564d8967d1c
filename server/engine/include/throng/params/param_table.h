#pragma once
// ParamTable: the patent's parameter table 21 (FIG. 8) as loaded from a parameter file.
//
// Layers, applied in this order to give one object's parameters:
//   defaults -> archetype (named, e.g. "cavalry"; what scene files reference) ->
//   override for the object id (all its collision bodies) -> override for (object id, collision id).
// Archetypes are stored fully resolved against the defaults (they are read once, at load);
// overrides are stored as patches because they apply on top of whichever archetype the scene
// gives the object. Ordered maps only: lookups here are load/spawn-time, and ordered iteration
// keeps every listing deterministic.
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "throng/params/group_table.h"
#include "throng/params/object_params.h"

namespace throng::params {

// A partial set of parameter values, applied in order through the validated setters.
struct ParamPatch {
  std::vector<std::pair<Param, double>> values;

  void apply(ObjectParams& o) const {
    for (const auto& [p, v] : values) o.set(p, v);
  }
  bool empty() const { return values.empty(); }
};

class ParamTable {
 public:
  // Override key meaning "every collision body of the object".
  static constexpr std::uint32_t kAllCollisions = 0xFFFFFFFFu;

  ParamTable() = default;
  // Reading one from its JSON file format: throng/params/params_json.h (target throng::scene).

  const ObjectParams& defaults() const { return defaults_; }
  void set_defaults(const ObjectParams& p);  // validates

  void set_archetype(const std::string& name, const ObjectParams& p);  // validates
  const ObjectParams* find_archetype(std::string_view name) const;
  // Throws std::invalid_argument("unknown archetype 'x'").
  const ObjectParams& archetype(std::string_view name) const;
  std::vector<std::string> archetype_names() const;  // sorted

  // collision_id = kAllCollisions for an object-wide override. Replaces an existing one.
  void set_override(std::uint32_t object_id, std::uint32_t collision_id, ParamPatch patch);
  const ParamPatch* find_override(std::uint32_t object_id, std::uint32_t collision_id) const;

  // The parameters of one collision body. An empty archetype name means "defaults".
  ObjectParams resolve(std::string_view archetype_name, std::uint32_t object_id, std::uint32_t collision_id = 0) const;

  const GroupTable& groups() const { return groups_; }
  GroupTable& groups() { return groups_; }

 private:
  ObjectParams defaults_;
  std::map<std::string, ObjectParams, std::less<>> archetypes_;
  std::map<std::pair<std::uint32_t, std::uint32_t>, ParamPatch> overrides_;
  GroupTable groups_;
};

}  // namespace throng::params
