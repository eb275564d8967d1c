// Reading a ParamTable from JSON (format in server/engine/data/FORMATS.md). Every field is checked
// where it is read so the error can name its JSON path ("archetypes.cavalry.weight").
#include <cmath>
#include <set>
#include <string>

#include "json_util.h"
#include "throng/params/config_error.h"
#include "throng/params/param_table.h"
#include "throng/params/params_json.h"

namespace throng::params {
namespace {

using detail::json;

constexpr int kParamFileVersion = 1;

template <typename Enum, typename Parser>
double read_category(const json& j, const std::string& path, Parser parse, std::string_view names) {
  if (!j.is_string()) detail::fail(path, std::string("expected one of ") + std::string(names) + ", got " + j.type_name());
  const std::string name = j.get<std::string>();
  const std::optional<Enum> v = parse(name);
  if (!v) detail::fail(path, "unknown category '" + name + "' (expected " + std::string(names) + ")");
  return static_cast<double>(*v);
}

double read_weight(const json& j, const std::string& path) {
  if (j.is_string()) {
    const std::string name = j.get<std::string>();
    if (auto c = parse_weight_class(name)) return weight_class_kg(*c);
    detail::fail(path, "unknown category '" + name + "' (expected " + std::string(weight_class_names_list()) +
                           " or a number in kg)");
  }
  return detail::read_number(j, path);
}

// "facing": [x, y] is stored as the equivalent yaw so a patch stays a list of (Param, value).
double read_facing_vector(const json& j, const std::string& path) {
  detail::expect_array(j, path);
  if (j.size() != 2) detail::fail(path, "expected [x, y]");
  const double x = detail::read_number(j[0], detail::index_path(path, 0));
  const double y = detail::read_number(j[1], detail::index_path(path, 1));
  if (!(x * x + y * y > 1e-18)) detail::fail(path, "facing vector has zero length");
  return std::atan2(y, x);
}

// The parameter fields of defaults / an archetype / an override, as a validated patch.
ParamPatch read_fields(const json& j, const std::string& path) {
  detail::expect_object(j, path);
  if (j.contains("weight") && j.contains("weight_kg")) {
    detail::fail(detail::key_path(path, "weight_kg"), "give either weight or weight_kg, not both");
  }
  if (j.contains("facing") && j.contains("facing_yaw_rad")) {
    detail::fail(detail::key_path(path, "facing_yaw_rad"), "give either facing or facing_yaw_rad, not both");
  }
  ParamPatch patch;
  for (const auto& item : j.items()) {  // key-sorted: the patch order is deterministic
    if (detail::is_comment_key(item.key())) continue;
    const std::string fpath = detail::key_path(path, item.key());
    const json& v = item.value();
    if (item.key() == "facing") {
      patch.values.emplace_back(Param::facing_yaw_rad, read_facing_vector(v, fpath));
      continue;
    }
    const std::optional<Param> p = try_parse_param(item.key());
    if (!p) detail::fail(fpath, "unknown parameter (known: " + param_names_list() + ", facing)");
    double value = 0.0;
    switch (*p) {
      case Param::kind: value = read_category<Kind>(v, fpath, parse_kind, kind_names_list()); break;
      case Param::character_type:
        value = read_category<CharacterType>(v, fpath, parse_character_type, character_type_names_list());
        break;
      case Param::weight_kg: value = read_weight(v, fpath); break;
      case Param::fixed: value = detail::read_bool(v, fpath) ? 1.0 : 0.0; break;
      default: value = detail::read_number(v, fpath); break;
    }
    if (auto why = check_param_value(*p, value)) detail::fail(fpath, *why);
    patch.values.emplace_back(*p, value);
  }
  return patch;
}

void check_group_refs(const ParamPatch& patch, const GroupTable& groups, const std::string& path) {
  for (const auto& [p, v] : patch.values) {
    if (p != Param::group_id || v == 0.0) continue;
    const auto id = static_cast<std::uint32_t>(v);
    if (!groups.contains(id)) {
      detail::fail(detail::key_path(path, "group_id"), "unknown group " + std::to_string(id) + " (not in groups)");
    }
  }
}

MoraleConfig read_morale(const json& j) {
  const std::string path = "morale";
  detail::expect_object(j, path);
  detail::check_known_keys(j, path,
                           {"low_enter", "low_exit", "high_exit", "high_enter", "low_offset", "high_offset", "min_nearby"});
  MoraleConfig c;
  auto num = [&](const char* key, double& out) {
    if (j.contains(key)) out = detail::read_number(j.at(key), detail::key_path(path, key));
  };
  num("low_enter", c.low_enter);
  num("low_exit", c.low_exit);
  num("high_exit", c.high_exit);
  num("high_enter", c.high_enter);
  num("low_offset", c.low_offset);
  num("high_offset", c.high_offset);
  if (j.contains("min_nearby")) c.min_nearby = detail::read_uint(j.at("min_nearby"), "morale.min_nearby", 0, 1000000);
  c.validate();  // names "morale.<field>"
  return c;
}

void read_groups(const json& j, GroupTable& groups) {
  detail::expect_array(j, "groups");
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string path = detail::index_path("groups", i);
    const json& g = detail::expect_object(j[i], path);
    detail::check_known_keys(g, path, {"id", "morale", "morale_state", "member_count", "strength", "importance"});
    if (!g.contains("id")) detail::fail(path + ".id", "missing");
    const std::uint32_t id = detail::read_uint(g.at("id"), path + ".id", 1, kMaxGroupId);
    if (groups.contains(id)) detail::fail(path + ".id", "duplicate group id " + std::to_string(id));
    Group out;
    if (g.contains("morale")) out.base_morale = detail::read_number(g.at("morale"), path + ".morale");
    if (g.contains("morale_state")) {
      const std::string s = detail::read_string(g.at("morale_state"), path + ".morale_state");
      const std::optional<MoraleState> st = parse_morale_state(s);
      if (!st) detail::fail(path + ".morale_state", "unknown morale state '" + s + "' (expected low, normal, high)");
      out.morale_state = *st;
    }
    if (g.contains("member_count")) {
      out.member_count = detail::read_uint(g.at("member_count"), path + ".member_count", 0, 1000000);
    }
    if (g.contains("strength")) out.strength = detail::read_number(g.at("strength"), path + ".strength");
    if (g.contains("importance")) out.importance = detail::read_number(g.at("importance"), path + ".importance");
    validate_group(out, path);
    groups.set(id, out);
  }
}

void read_objects(const json& j, ParamTable& table) {
  detail::expect_array(j, "objects");
  std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string path = detail::index_path("objects", i);
    const json& o = detail::expect_object(j[i], path);
    detail::check_known_keys(o, path, {"object_id", "collision_id", "params"});
    if (!o.contains("object_id")) detail::fail(path + ".object_id", "missing");
    const std::uint32_t object_id = detail::read_uint(o.at("object_id"), path + ".object_id", 0, 0xFFFFFFFFu);
    std::uint32_t collision_id = ParamTable::kAllCollisions;
    if (o.contains("collision_id")) {
      collision_id = detail::read_uint(o.at("collision_id"), path + ".collision_id", 0, 0xFFFFFFFEu);
    }
    if (!seen.insert({object_id, collision_id}).second) {
      detail::fail(path, "duplicate override for object " + std::to_string(object_id) +
                             (collision_id == ParamTable::kAllCollisions ? std::string()
                                                                          : " collision " + std::to_string(collision_id)));
    }
    ParamPatch patch = o.contains("params") ? read_fields(o.at("params"), path + ".params") : ParamPatch{};
    check_group_refs(patch, table.groups(), path + ".params");
    table.set_override(object_id, collision_id, std::move(patch));
  }
}

}  // namespace

ParamTable param_table_from_json(const nlohmann::json& doc) {
  detail::expect_object(doc, "");
  detail::check_known_keys(doc, "", {"version", "defaults", "archetypes", "groups", "morale", "objects"});
  detail::check_version(doc, kParamFileVersion);
  ParamTable table;
  // Groups first so parameter rows can be checked for references to unknown groups.
  if (doc.contains("morale")) table.groups().set_morale_config(read_morale(doc.at("morale")));
  if (doc.contains("groups")) read_groups(doc.at("groups"), table.groups());
  if (doc.contains("defaults")) {
    const ParamPatch patch = read_fields(doc.at("defaults"), "defaults");
    check_group_refs(patch, table.groups(), "defaults");
    ObjectParams defaults = table.defaults();
    patch.apply(defaults);
    table.set_defaults(defaults);
  }
  if (doc.contains("archetypes")) {
    const json& arch = detail::expect_object(doc.at("archetypes"), "archetypes");
    for (const auto& item : arch.items()) {
      if (detail::is_comment_key(item.key())) continue;
      const std::string path = detail::key_path("archetypes", item.key());
      if (item.key().empty()) detail::fail(path, "archetype name must not be empty");
      const ParamPatch patch = read_fields(item.value(), path);
      check_group_refs(patch, table.groups(), path);
      ObjectParams p = table.defaults();
      patch.apply(p);
      table.set_archetype(item.key(), p);
    }
  }
  if (doc.contains("objects")) read_objects(doc.at("objects"), table);
  return table;
}

ParamTable parse_param_table(std::string_view json_text, std::string_view source_name) {
  return param_table_from_json(detail::parse_json_text(json_text, source_name));
}

ParamTable load_param_table(const std::string& file_path) {
  return param_table_from_json(detail::read_json_file(file_path));
}

}  // namespace throng::params
