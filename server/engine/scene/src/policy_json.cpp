// Reading a PushPolicy from JSON (format in server/engine/data/FORMATS.md). This file only maps
// JSON to the C++ structs and reports type / name errors; range checks live in the PushPolicy
// constructor and validate_pair_rules so code-built policies get the same checks and paths.
#include <string>

#include "json_util.h"
#include "throng/params/params_json.h"
#include "throng/params/push_policy.h"

namespace throng::params {
namespace {

using detail::json;

constexpr int kPolicyVersion = 1;

template <typename Enum, typename Parser>
std::uint32_t read_category_set(const json& j, const std::string& path, Parser parse, std::string_view names) {
  auto one = [&](const json& item, const std::string& item_path) -> std::uint32_t {
    const std::string name = detail::read_string(item, item_path);
    const std::optional<Enum> v = parse(name);
    if (!v) detail::fail(item_path, "unknown category '" + name + "' (expected " + std::string(names) + ")");
    return category_bit(*v);
  };
  if (j.is_string()) return one(j, path);
  detail::expect_array(j, path);
  std::uint32_t bits = 0u;
  for (std::size_t i = 0; i < j.size(); ++i) bits |= one(j[i], detail::index_path(path, i));
  return bits;  // an empty list gives 0, which SidePredicate::validate reports
}

double read_weight_bound(const json& j, const std::string& path) {
  if (j.is_string()) {
    const std::string name = j.get<std::string>();
    if (auto c = parse_weight_class(name)) return weight_class_kg(*c);
    detail::fail(path, "unknown category '" + name + "' (expected " + std::string(weight_class_names_list()) +
                           " or a number in kg)");
  }
  return detail::read_number_in(j, path, 0.0, 1.0e6);
}

SidePredicate read_predicate(const json& j, const std::string& path) {
  detail::expect_object(j, path);
  detail::check_known_keys(j, path,
                           {"character_type", "kind", "faction", "weight_at_least", "weight_at_most", "fixed", "ranges"});
  SidePredicate p;
  if (j.contains("character_type")) {
    p.character_types = read_category_set<CharacterType>(j.at("character_type"), detail::key_path(path, "character_type"),
                                                         parse_character_type, character_type_names_list());
  }
  if (j.contains("kind")) {
    p.kinds = read_category_set<Kind>(j.at("kind"), detail::key_path(path, "kind"), parse_kind, kind_names_list());
  }
  if (j.contains("faction")) {
    p.relations = read_category_set<FactionRelation>(j.at("faction"), detail::key_path(path, "faction"),
                                                     parse_faction_relation, faction_relation_names_list());
  }
  if (j.contains("weight_at_least")) {
    p.weight_min_kg = read_weight_bound(j.at("weight_at_least"), detail::key_path(path, "weight_at_least"));
  }
  if (j.contains("weight_at_most")) {
    p.weight_max_kg = read_weight_bound(j.at("weight_at_most"), detail::key_path(path, "weight_at_most"));
  }
  if (j.contains("fixed")) p.fixed = detail::read_bool(j.at("fixed"), detail::key_path(path, "fixed"));
  if (j.contains("ranges")) {
    const std::string rpath = detail::key_path(path, "ranges");
    const json& ranges = detail::expect_object(j.at("ranges"), rpath);
    for (const auto& item : ranges.items()) {  // nlohmann objects are key-sorted: deterministic order
      if (detail::is_comment_key(item.key())) continue;
      const std::string ppath = detail::key_path(rpath, item.key());
      const std::optional<Param> param = try_parse_param(item.key());
      if (!param) detail::fail(ppath, "unknown parameter (known: " + param_names_list() + ")");
      detail::expect_object(item.value(), ppath);
      detail::check_known_keys(item.value(), ppath, {"min", "max"});
      ParamBound b{*param};
      if (item.value().contains("min")) b.min = detail::read_number(item.value().at("min"), ppath + ".min");
      if (item.value().contains("max")) b.max = detail::read_number(item.value().at("max"), ppath + ".max");
      p.ranges.push_back(b);
    }
  }
  return p;
}

PairRule read_rule(const json& j, const std::string& path) {
  detail::expect_object(j, path);
  detail::check_known_keys(j, path, {"name", "a", "b", "share_b"});
  if (!j.contains("name")) detail::fail(path + ".name", "missing");
  if (!j.contains("share_b")) detail::fail(path + ".share_b", "missing");
  PairRule r;
  r.name = detail::read_string(j.at("name"), path + ".name");
  if (j.contains("a")) r.a = read_predicate(j.at("a"), path + ".a");
  if (j.contains("b")) r.b = read_predicate(j.at("b"), path + ".b");
  r.share_b = detail::read_number(j.at("share_b"), path + ".share_b");
  return r;
}

Term read_term(const json& j, const std::string& path) {
  detail::expect_object(j, path);
  detail::check_known_keys(j, path, {"param", "weight", "scale", "invert"});
  if (!j.contains("param")) detail::fail(path + ".param", "missing");
  Term t;
  const std::string name = detail::read_string(j.at("param"), path + ".param");
  const std::optional<TermInput> input = parse_term_input(name);
  if (!input) {
    detail::fail(path + ".param", "unknown param name '" + name + "' (known: " + term_input_names_list() + ")");
  }
  t.input = *input;
  if (j.contains("weight")) t.weight = detail::read_number(j.at("weight"), path + ".weight");
  if (j.contains("scale")) t.scale = detail::read_number(j.at("scale"), path + ".scale");
  if (j.contains("invert")) t.invert = detail::read_bool(j.at("invert"), path + ".invert");
  return t;
}

}  // namespace

PushPolicy push_policy_from_json(const nlohmann::json& doc) {
  detail::expect_object(doc, "");
  detail::check_known_keys(doc, "", {"version", "mode", "home_faction", "terms", "pair_rules"});
  detail::check_version(doc, kPolicyVersion);
  if (!doc.contains("mode")) detail::fail("mode", "missing (expected ratio, priority or half)");
  const std::string mode_name = detail::read_string(doc.at("mode"), "mode");
  const std::optional<PushMode> mode = parse_push_mode(mode_name);
  if (!mode) detail::fail("mode", "unknown mode '" + mode_name + "' (expected ratio, priority or half)");

  std::uint32_t home = kDefaultHomeFaction;
  if (doc.contains("home_faction")) home = detail::read_uint(doc.at("home_faction"), "home_faction", 1, kMaxFaction);

  std::vector<Term> terms;
  if (doc.contains("terms")) {
    const json& arr = detail::expect_array(doc.at("terms"), "terms");
    for (std::size_t i = 0; i < arr.size(); ++i) terms.push_back(read_term(arr[i], detail::index_path("terms", i)));
  }
  std::vector<PairRule> rules;
  if (doc.contains("pair_rules")) {
    const json& arr = detail::expect_array(doc.at("pair_rules"), "pair_rules");
    for (std::size_t i = 0; i < arr.size(); ++i) {
      rules.push_back(read_rule(arr[i], detail::index_path("pair_rules", i)));
    }
  }
  return PushPolicy(*mode, std::move(terms), std::move(rules), home);
}

PushPolicy parse_push_policy(std::string_view json_text, std::string_view source_name) {
  return push_policy_from_json(detail::parse_json_text(json_text, source_name));
}

PushPolicy load_push_policy(const std::string& file_path) {
  return push_policy_from_json(detail::read_json_file(file_path));
}

}  // namespace throng::params
