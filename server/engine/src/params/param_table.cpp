#include "throng/params/param_table.h"

#include <stdexcept>

namespace throng::params {

void ParamTable::set_defaults(const ObjectParams& p) {
  p.validate();
  defaults_ = p;
}

void ParamTable::set_archetype(const std::string& name, const ObjectParams& p) {
  if (name.empty()) throw std::invalid_argument("archetype name must not be empty");
  p.validate();
  archetypes_.insert_or_assign(name, p);
}

const ObjectParams* ParamTable::find_archetype(std::string_view name) const {
  const auto it = archetypes_.find(name);
  return it == archetypes_.end() ? nullptr : &it->second;
}

const ObjectParams& ParamTable::archetype(std::string_view name) const {
  if (const ObjectParams* p = find_archetype(name)) return *p;
  throw std::invalid_argument("unknown archetype '" + std::string(name) + "'");
}

std::vector<std::string> ParamTable::archetype_names() const {
  std::vector<std::string> out;
  out.reserve(archetypes_.size());
  for (const auto& [name, p] : archetypes_) out.push_back(name);
  return out;
}

void ParamTable::set_override(std::uint32_t object_id, std::uint32_t collision_id, ParamPatch patch) {
  // Apply once to a scratch row so a bad value fails here, not when the object spawns.
  ObjectParams scratch = defaults_;
  patch.apply(scratch);
  overrides_.insert_or_assign({object_id, collision_id}, std::move(patch));
}

const ParamPatch* ParamTable::find_override(std::uint32_t object_id, std::uint32_t collision_id) const {
  const auto it = overrides_.find({object_id, collision_id});
  return it == overrides_.end() ? nullptr : &it->second;
}

ObjectParams ParamTable::resolve(std::string_view archetype_name, std::uint32_t object_id,
                                 std::uint32_t collision_id) const {
  ObjectParams p = archetype_name.empty() ? defaults_ : archetype(archetype_name);
  if (const ParamPatch* all = find_override(object_id, kAllCollisions)) all->apply(p);
  if (collision_id != kAllCollisions) {
    if (const ParamPatch* one = find_override(object_id, collision_id)) one->apply(p);
  }
  p.object_id = object_id;
  p.collision_id = collision_id;
  return p;
}

}  // namespace throng::params
