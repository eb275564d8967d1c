// Parameter records, push policy and groups <-> bytes (see param_codec.h).
#include "world/param_codec.h"

#include <cstring>
#include <exception>
#include <stdexcept>
#include <string>

namespace throng::detail {
namespace {

// Cursor over a pre-sized block: one bounds check for a whole record array instead of one per field.
struct Cursor {
  std::uint8_t* p;
  template <class T>
  void put(T v) {
    std::memcpy(p, &v, sizeof(T));
    p += sizeof(T);
  }
};
struct ReadCursor {
  const std::uint8_t* p;
  template <class T>
  T get() {
    T v;
    std::memcpy(&v, p, sizeof(T));
    p += sizeof(T);
    return v;
  }
};

template <class Enum>
Enum checked_enum(std::uint8_t v, std::uint8_t max, const char* what, const ByteReader& r) {
  if (v > max) r.fail(std::string(what) + ": value " + std::to_string(v) + " out of range");
  return static_cast<Enum>(v);
}

void put_predicate(ByteWriter& w, const params::SidePredicate& p) {
  w.put(p.character_types);
  w.put(p.kinds);
  w.put(p.relations);
  w.put(p.weight_min_kg);
  w.put(p.weight_max_kg);
  w.put(static_cast<std::uint8_t>(!p.fixed ? 0 : (*p.fixed ? 2 : 1)));
  w.put(static_cast<std::uint32_t>(p.ranges.size()));
  for (const params::ParamBound& b : p.ranges) {
    w.put(static_cast<std::uint8_t>(b.param));
    w.put(b.min);
    w.put(b.max);
  }
}

params::SidePredicate get_predicate(ByteReader& r) {
  params::SidePredicate p;
  p.character_types = r.get<std::uint32_t>("rule.character_types");
  p.kinds = r.get<std::uint32_t>("rule.kinds");
  p.relations = r.get<std::uint32_t>("rule.relations");
  p.weight_min_kg = r.get<double>("rule.weight_min");
  p.weight_max_kg = r.get<double>("rule.weight_max");
  const auto fixed = r.get<std::uint8_t>("rule.fixed");
  if (fixed > 2) r.fail("rule.fixed: value " + std::to_string(fixed));
  if (fixed != 0) p.fixed = fixed == 2;
  const std::uint32_t n = r.get_count("rule.ranges", 1024, 17);
  for (std::uint32_t k = 0; k < n; ++k) {
    params::ParamBound b;
    b.param = checked_enum<params::Param>(r.get<std::uint8_t>("range.param"), params::kParamCount - 1, "range.param", r);
    b.min = r.get<double>("range.min");
    b.max = r.get<double>("range.max");
    p.ranges.push_back(b);
  }
  return p;
}

}  // namespace

void put_params(ByteWriter& w, std::span<const params::ObjectParams> records, ObjectIdField ids,
                std::span<const std::uint32_t> order) {
  const bool with_id = ids == ObjectIdField::kept;
  Cursor c{w.grow(records.size() * (with_id ? kParamsRecordBytes : kParamsRecordBytesWithoutId))};
  for (std::size_t i = 0; i < records.size(); ++i) {
    const params::ObjectParams& p = records[order.empty() ? i : order[i]];
    if (with_id) c.put(p.object_id);
    c.put(p.collision_id);
    c.put(static_cast<std::uint8_t>(p.kind));
    c.put(p.importance);
    c.put(p.size_m);
    c.put(p.weight_kg);
    c.put(p.equipment_level);
    c.put(p.softness);
    c.put(p.speed_mps);
    c.put(p.facing_x);
    c.put(p.facing_y);
    c.put(static_cast<std::uint8_t>(p.fixed ? 1 : 0));
    c.put(p.faction);
    c.put(static_cast<std::uint8_t>(p.character_type));
    c.put(p.height_above_ground_m);
    c.put(p.group_id);
    c.put(p.camera_distance_m);
    c.put(p.hp);
    c.put(p.level);
    c.put(p.collision_group);
    c.put(p.collision_mask);
  }
}

void get_params(ByteReader& r, std::size_t n, std::vector<params::ObjectParams>& out, const char* what, ObjectIdField ids) {
  const bool with_id = ids == ObjectIdField::kept;
  ReadCursor c{r.take(n * (with_id ? kParamsRecordBytes : kParamsRecordBytesWithoutId), what)};
  out.resize(n);
  for (params::ObjectParams& p : out) {
    p.object_id = with_id ? c.get<std::uint32_t>() : 0;
    p.collision_id = c.get<std::uint32_t>();
    p.kind = checked_enum<params::Kind>(c.get<std::uint8_t>(), 4, "params.kind", r);
    p.importance = c.get<double>();
    p.size_m = c.get<double>();
    p.weight_kg = c.get<double>();
    p.equipment_level = c.get<double>();
    p.softness = c.get<double>();
    p.speed_mps = c.get<double>();
    p.facing_x = c.get<double>();
    p.facing_y = c.get<double>();
    p.fixed = checked_enum<std::uint8_t>(c.get<std::uint8_t>(), 1, "params.fixed", r) != 0;
    p.faction = c.get<std::uint8_t>();
    p.character_type = checked_enum<params::CharacterType>(c.get<std::uint8_t>(), 3, "params.character_type", r);
    p.height_above_ground_m = c.get<double>();
    p.group_id = c.get<std::uint32_t>();
    p.camera_distance_m = c.get<double>();
    p.hp = c.get<double>();
    p.level = c.get<double>();
    p.collision_group = c.get<std::uint32_t>();
    p.collision_mask = c.get<std::uint32_t>();
    // Every value within its parameter's range, as the setters keep them (found by fuzzing: NaN
    // parameters were accepted and the next step threw from the push policy's score).
    try {
      p.validate();
    } catch (const std::invalid_argument& e) {
      r.fail(std::string(what) + ": " + e.what());
    }
  }
}

void put_policy(ByteWriter& w, const params::PushPolicy& policy) {
  w.put(static_cast<std::uint8_t>(policy.mode()));
  w.put(policy.home_faction());
  w.put(static_cast<std::uint32_t>(policy.terms().size()));
  for (const params::Term& t : policy.terms()) {
    w.put(static_cast<std::uint8_t>(t.input));
    w.put(t.weight);
    w.put(t.scale);
    w.put(static_cast<std::uint8_t>(t.invert ? 1 : 0));
  }
  w.put(static_cast<std::uint32_t>(policy.rules().size()));
  for (const params::PairRule& rule : policy.rules()) {
    w.put_string(rule.name);
    put_predicate(w, rule.a);
    put_predicate(w, rule.b);
    w.put(rule.share_b);
  }
}

params::PushPolicy get_policy(ByteReader& r) {
  const auto mode = checked_enum<params::PushMode>(r.get<std::uint8_t>("policy.mode"), 2, "policy.mode", r);
  const auto home = r.get<std::uint32_t>("policy.home_faction");
  std::vector<params::Term> terms(r.get_count("policy.terms", 1024, 18));
  for (params::Term& t : terms) {
    t.input = checked_enum<params::TermInput>(r.get<std::uint8_t>("term.input"), params::kTermInputCount - 1,
                                              "term.input", r);
    t.weight = r.get<double>("term.weight");
    t.scale = r.get<double>("term.scale");
    t.invert = r.get_bool("term.invert");
  }
  std::vector<params::PairRule> rules(r.get_count("policy.rules", params::kMaxPairRules, 40));
  for (params::PairRule& rule : rules) {
    rule.name = r.get_string("rule.name", 4096);
    rule.a = get_predicate(r);
    rule.b = get_predicate(r);
    rule.share_b = r.get<double>("rule.share_b");
  }
  try {
    return params::PushPolicy(mode, std::move(terms), std::move(rules), home);
  } catch (const std::exception& e) {
    r.fail(std::string("push policy does not validate: ") + e.what());
  }
}

void put_groups(ByteWriter& w, const params::GroupTable& groups) {
  w.put(static_cast<std::uint32_t>(groups.size()));
  // Ascending ids without groups.ids()' vector: the save path must not allocate.
  std::uint32_t written = 0;
  for (std::uint32_t id = 1; id <= params::kMaxGroupId && written < groups.size(); ++id) {
    const params::Group* g = groups.find(id);
    if (g == nullptr) continue;
    w.put(id);
    w.put(g->base_morale);
    w.put(static_cast<std::uint8_t>(g->morale_state));
    w.put(g->member_count);
    w.put(g->strength);
    w.put(g->importance);
    ++written;
  }
}

std::vector<std::pair<std::uint32_t, params::Group>> get_groups(ByteReader& r) {
  std::vector<std::pair<std::uint32_t, params::Group>> out(r.get_count("groups", params::kMaxGroupId, 33));
  std::uint32_t previous = 0;
  for (auto& [id, g] : out) {
    id = r.get<std::uint32_t>("group.id");
    if (id <= previous || id > params::kMaxGroupId) r.fail("group ids not ascending in [1, 65535]: " + std::to_string(id));
    previous = id;
    g.base_morale = r.get<double>("group.base_morale");
    g.morale_state = checked_enum<params::MoraleState>(r.get<std::uint8_t>("group.morale_state"), 2, "group.morale_state", r);
    g.member_count = r.get<std::uint32_t>("group.member_count");
    g.strength = r.get<double>("group.strength");
    g.importance = r.get<double>("group.importance");
  }
  return out;
}

}  // namespace throng::detail
