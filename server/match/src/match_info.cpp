#include "match_info.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <vector>

#include <fmt/format.h>

#include "throng/params/group_table.h"
#include "throng/params/pair_rules.h"
#include "throng/world/world.h"

namespace throng::match {
namespace {

void append_predicate(std::string& s, const params::SidePredicate& p) {
  s += fmt::format("{{ct={},kind={},rel={},wmin={},wmax={},fixed={}", p.character_types, p.kinds, p.relations,
                   p.weight_min_kg, p.weight_max_kg, p.fixed ? (*p.fixed ? "1" : "0") : "-");
  for (const params::ParamBound& b : p.ranges) {
    s += fmt::format(",{}[{},{}]", params::param_name(b.param), b.min, b.max);
  }
  s += "}";
}

void append_params(std::string& s, const params::ObjectParams& p) {
  for (std::size_t k = 0; k < params::kParamCount; ++k) {
    const auto param = static_cast<params::Param>(k);
    s += fmt::format("{}={};", params::param_name(param), p.get(param));
  }
}

std::uint16_t to_mm16(double m) {
  const double mm = std::round(m * 1000.0);
  return static_cast<std::uint16_t>(std::clamp(mm, 0.0, 65535.0));
}

struct Bounds {
  double min_x = std::numeric_limits<double>::infinity();
  double min_y = std::numeric_limits<double>::infinity();
  double max_x = -std::numeric_limits<double>::infinity();
  double max_y = -std::numeric_limits<double>::infinity();
  void add(double x, double y, double rx, double ry) {
    min_x = std::min(min_x, x - rx);
    max_x = std::max(max_x, x + rx);
    min_y = std::min(min_y, y - ry);
    max_y = std::max(max_y, y + ry);
  }
  bool empty() const { return !(min_x <= max_x); }
};

std::string read_file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

std::uint64_t fnv1a64(std::string_view text, std::uint64_t h) {
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::string canonical_policy_text(const params::PushPolicy& policy) {
  std::string s = fmt::format("mode={};home={};", params::push_mode_name(policy.mode()), policy.home_faction());
  for (const params::Term& t : policy.terms()) {
    s += fmt::format("term={},{},{},{};", params::term_input_name(t.input), t.weight, t.scale, t.invert ? 1 : 0);
  }
  for (const params::PairRule& r : policy.rules()) {
    s += fmt::format("rule={},{},", r.name, r.share_b);
    append_predicate(s, r.a);
    append_predicate(s, r.b);
    s += ";";
  }
  return s;
}

std::string canonical_table_text(const params::ParamTable& table, const scene::DocumentSource& source) {
  std::string s = "defaults:";
  append_params(s, table.defaults());
  for (const std::string& name : table.archetype_names()) {
    s += "\narchetype " + name + ":";
    append_params(s, table.archetype(name));
  }
  const params::GroupTable& groups = table.groups();
  const params::MoraleConfig& m = groups.morale_config();
  s += fmt::format("\nmorale:{},{},{},{},{},{},{}", m.low_enter, m.low_exit, m.high_exit, m.high_enter, m.low_offset,
                   m.high_offset, m.min_nearby);
  for (std::uint32_t id : groups.ids()) {
    const params::Group& g = groups.at(id);
    s += fmt::format("\ngroup {}:{},{},{},{},{}", id, g.base_morale, static_cast<int>(g.morale_state), g.member_count,
                     g.strength, g.importance);
  }
  if (!source.file.empty()) {
    s += "\nfile:" + read_file_text(source.file);
  } else if (!source.inline_json.empty()) {
    s += "\ninline:" + source.inline_json;
  }
  return s;
}

protocol::MatchInfo build_match_info(const MatchInfoSource& src) {
  const World& world = src.world;
  protocol::MatchInfo info;
  info.protocol_version = protocol::kProtocolVersion;
  info.match_id = src.match_id;
  info.scene_name = src.scene.name;
  info.tick_hz = src.config.tick_hz;
  info.start_tick = 0;
  info.param_table_hash = fnv1a64(canonical_table_text(src.table, src.scene.params));
  info.push_policy_hash = policy_hash(world.policy());
  info.param_version = 0;
  info.max_clients = src.config.max_clients;
  info.interest_radius_m = static_cast<float>(src.config.interest.radius_m);
  info.state = protocol::MatchState::running;
  info.archetypes = src.table.archetype_names();

  Bounds bounds;
  // Scenery, in scene order.
  for (std::size_t i = 0; i < src.scene.scenery.size() && i < src.scenery_ids.size(); ++i) {
    const scene::Scenery& sc = src.scene.scenery[i];
    protocol::SceneryShape shape;
    shape.id = src.scenery_ids[i].value;
    shape.archetype = sc.archetype;
    shape.softness = static_cast<float>(world.params(src.scenery_ids[i]).softness);
    switch (sc.kind) {
      case scene::SceneryKind::box: {
        shape.kind = protocol::ShapeKind::box;
        const double yaw = sc.yaw_deg * (std::numbers::pi / 180.0);
        shape.cx = static_cast<float>(sc.centre.x);
        shape.cy = static_cast<float>(sc.centre.y);
        shape.cz = static_cast<float>(sc.centre.z);
        shape.hx = static_cast<float>(sc.half_extents_m.x);
        shape.hy = static_cast<float>(sc.half_extents_m.y);
        shape.hz = static_cast<float>(sc.half_extents_m.z);
        shape.yaw_rad = static_cast<float>(yaw);
        const double c = std::abs(std::cos(yaw));
        const double s = std::abs(std::sin(yaw));
        bounds.add(sc.centre.x, sc.centre.y, sc.half_extents_m.x * c + sc.half_extents_m.y * s,
                   sc.half_extents_m.x * s + sc.half_extents_m.y * c);
        break;
      }
      case scene::SceneryKind::cylinder:
        shape.kind = protocol::ShapeKind::cylinder;
        shape.cx = static_cast<float>(sc.centre.x);
        shape.cy = static_cast<float>(sc.centre.y);
        shape.cz = static_cast<float>(sc.centre.z);
        shape.radius = static_cast<float>(sc.radius_m);
        shape.half_height = static_cast<float>(sc.half_height_m);
        bounds.add(sc.centre.x, sc.centre.y, sc.radius_m, sc.radius_m);
        break;
      case scene::SceneryKind::mesh:
        shape.kind = protocol::ShapeKind::mesh;
        shape.vertices.reserve(sc.vertices.size() * 3);
        for (const Vec3& v : sc.vertices) {
          shape.vertices.push_back(static_cast<float>(v.x));
          shape.vertices.push_back(static_cast<float>(v.y));
          shape.vertices.push_back(static_cast<float>(v.z));
          bounds.add(v.x, v.y, 0.0, 0.0);
        }
        shape.triangles.reserve(sc.triangles.size() * 3);
        for (const auto& t : sc.triangles) shape.triangles.insert(shape.triangles.end(), t.begin(), t.end());
        break;
    }
    info.scenery.push_back(std::move(shape));
  }

  // Archetype of every body: the spawn group it was created by (creation order = spawns order).
  std::vector<std::uint8_t> archetype_of_slot;
  {
    std::size_t k = 0;
    for (const scene::SpawnGroup& g : src.scene.spawns) {
      const auto it = std::lower_bound(info.archetypes.begin(), info.archetypes.end(), g.archetype);
      const auto index = static_cast<std::size_t>(it - info.archetypes.begin());
      const auto code = static_cast<std::uint8_t>(std::min<std::size_t>(index, 255));
      for (std::uint32_t j = 0; j < g.count && k < src.body_ids.size(); ++j, ++k) {
        const std::uint32_t slot = src.body_ids[k].index();
        if (archetype_of_slot.size() <= slot) archetype_of_slot.resize(slot + 1, 0);
        archetype_of_slot[slot] = code;
      }
    }
  }

  // Roster in the world's dense order at construction (the World re-sorts later; the match maps ids).
  const std::size_t n = world.body_count();
  protocol::Roster& r = info.roster;
  r.id.resize(n);
  r.radius_mm.resize(n);
  r.half_height_mm.resize(n);
  r.faction.resize(n);
  r.character_type.resize(n);
  r.archetype.resize(n);
  const auto xs = world.pos_x();
  const auto ys = world.pos_y();
  const auto radius = world.radius();
  const auto hh = world.half_height();
  for (std::size_t d = 0; d < n; ++d) {
    const ObjectId id = world.id_at(d);
    r.id[d] = id.value;
    r.radius_mm[d] = to_mm16(radius[d]);
    r.half_height_mm[d] = to_mm16(hh[d]);
    update_roster_entry(r, d, world.params(id));
    r.archetype[d] = id.index() < archetype_of_slot.size() ? archetype_of_slot[id.index()] : 0;
    bounds.add(xs[d], ys[d], radius[d], radius[d]);
  }
  if (bounds.empty()) bounds.add(0.0, 0.0, 0.0, 0.0);
  info.world_min_x = static_cast<float>(bounds.min_x - kWorldBoundsMargin_m);
  info.world_min_y = static_cast<float>(bounds.min_y - kWorldBoundsMargin_m);
  info.world_max_x = static_cast<float>(bounds.max_x + kWorldBoundsMargin_m);
  info.world_max_y = static_cast<float>(bounds.max_y + kWorldBoundsMargin_m);
  return info;
}

void update_roster_entry(protocol::Roster& roster, std::size_t d, const params::ObjectParams& p) {
  roster.faction[d] = p.faction;
  roster.character_type[d] = static_cast<std::uint8_t>(p.character_type);
}

}  // namespace throng::match
