// JSON -> SceneDef. Structure and meaning of the fields: scene_json.h.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "field_reader.h"
#include "kind_names.h"
#include "world/settings_fields.h"
#include "throng/core/object_id.h"
#include "throng/params/object_params.h"
#include "throng/scene/scene_error.h"
#include "throng/scene/scene_json.h"

namespace throng::scene {
namespace {

using detail::FieldReader;

// Generous bounds that only catch nonsense (a unit mix-up, a stray exponent); the World applies
// its own, tighter limits where it has them.
constexpr double kMaxCoord_m = 1e6;
constexpr double kMaxSize_m = 1e5;
constexpr double kMaxBodyRadius_m = 100.0;  // BodyDef's documented range
constexpr double kMaxSpeed_mps = 1000.0;

std::string item_path(const std::string& array_path, std::size_t i) {
  return array_path + "[" + std::to_string(i) + "]";
}

Vec2 checked(Vec2 v, const std::string& path) {
  if (std::fabs(v.x) > kMaxCoord_m || std::fabs(v.y) > kMaxCoord_m)
    throw SceneError(path, "coordinates must be within +-" + detail::format_number(kMaxCoord_m) + " m");
  return v;
}
Vec3 checked(Vec3 v, const std::string& path) {
  checked(Vec2{v.x, v.y}, path);
  if (std::fabs(v.z) > kMaxCoord_m)
    throw SceneError(path, "coordinates must be within +-" + detail::format_number(kMaxCoord_m) + " m");
  return v;
}

template <typename E, std::size_t N>
E read_kind(FieldReader& r, const std::array<std::pair<E, std::string_view>, N>& table) {
  const std::string name = r.string("type", std::nullopt);
  const auto kind = detail::kind_from_name(table, name);
  if (!kind) throw SceneError(r.path_of("type"), "unknown type '" + name + "' (known: " + detail::kind_list(table) + ")");
  return *kind;
}

WorldSettings read_settings(const nlohmann::json& j, const std::string& path) {
  FieldReader r(j, path);
  WorldSettings s;  // defaults for absent keys
  for (const auto& f : throng::detail::kSettingFields) {
    switch (f.type) {
      case throng::detail::SettingField::Type::f64:
        s.*f.f64 = r.number(f.key, s.*f.f64, f.min, f.max);
        break;
      case throng::detail::SettingField::Type::u32: {
        const auto v = r.integer(f.key, s.*f.u32, static_cast<std::uint64_t>(f.max));
        if (static_cast<double>(v) < f.min) throw SceneError(r.path_of(f.key), "must be >= " + detail::format_number(f.min));
        s.*f.u32 = static_cast<std::uint32_t>(v);
        break;
      }
      case throng::detail::SettingField::Type::boolean:
        s.*f.boolean = r.boolean(f.key, s.*f.boolean);
        break;
    }
  }
  r.finish();
  // The World's own check is the authority on ranges; ours above only give better paths.
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    throw SceneError(path, e.what());
  }
  return s;
}

DocumentSource read_source(const nlohmann::json* j, const std::string& path, const std::string& base_dir) {
  DocumentSource src;
  if (!j) return src;
  if (j->is_string()) {
    src.file = j->get<std::string>();
    if (src.file.empty()) throw SceneError(path, "file path must not be empty");
    // Absolute, so the scene means the same thing wherever it is dumped and reloaded from.
    if (!base_dir.empty() && std::filesystem::path(src.file).is_relative())
      src.file = std::filesystem::absolute(std::filesystem::path(base_dir) / src.file).lexically_normal().string();
  } else if (j->is_object()) {
    src.inline_json = j->dump();
  } else {
    throw SceneError(path, "must be a file path (string), an inline object, or null for the defaults");
  }
  return src;
}

std::vector<Vec3> read_vertices(const nlohmann::json* j, const std::string& path) {
  if (!j || !j->is_array() || j->empty()) throw SceneError(path, "must be a non-empty array of [x, y, z]");
  std::vector<Vec3> out;
  for (std::size_t i = 0; i < j->size(); ++i) {
    const auto p = item_path(path, i);
    const auto& v = (*j)[i];
    if (!v.is_array() || v.size() != 3) throw SceneError(p, "must be an array of 3 numbers");
    out.push_back(checked(Vec3{detail::finite_number(v[0], p + "[0]"), detail::finite_number(v[1], p + "[1]"),
                               detail::finite_number(v[2], p + "[2]")},
                          p));
  }
  return out;
}

std::vector<std::array<std::uint32_t, 3>> read_triangles(const nlohmann::json* j, const std::string& path,
                                                         std::size_t vertex_count) {
  if (!j || !j->is_array() || j->empty()) throw SceneError(path, "must be a non-empty array of [i, j, k]");
  std::vector<std::array<std::uint32_t, 3>> out;
  for (std::size_t i = 0; i < j->size(); ++i) {
    const auto p = item_path(path, i);
    const auto& t = (*j)[i];
    if (!t.is_array() || t.size() != 3) throw SceneError(p, "must be an array of 3 vertex indices");
    std::array<std::uint32_t, 3> tri{};
    for (std::size_t k = 0; k < 3; ++k) {
      const bool index = t[k].is_number_integer() && (t[k].is_number_unsigned() || t[k].get<std::int64_t>() >= 0);
      if (!index || t[k].get<std::uint64_t>() >= vertex_count)
        throw SceneError(p + "[" + std::to_string(k) + "]",
                         "must be a vertex index in [0, " + std::to_string(vertex_count) + ")");
      tri[k] = static_cast<std::uint32_t>(t[k].get<std::uint64_t>());
    }
    out.push_back(tri);
  }
  return out;
}

Scenery read_scenery(const nlohmann::json& j, const std::string& path) {
  FieldReader r(j, path);
  Scenery s;
  s.kind = read_kind(r, detail::kSceneryKinds);
  s.archetype = r.string("archetype", s.archetype);
  if (const auto* p = r.raw("params")) s.params = detail::read_param_overrides(*p, r.path_of("params"));
  switch (s.kind) {
    case SceneryKind::box: {
      s.centre = checked(r.vec3("centre", std::nullopt), r.path_of("centre"));
      s.half_extents_m = r.vec3("half_extents_m", std::nullopt);
      const double he[3] = {s.half_extents_m.x, s.half_extents_m.y, s.half_extents_m.z};
      for (int k = 0; k < 3; ++k) {
        const auto p = r.path_of("half_extents_m") + "[" + std::to_string(k) + "]";
        if (!(he[k] > 0.0)) throw SceneError(p, "must be > 0");
        if (he[k] > kMaxSize_m) throw SceneError(p, "must be <= " + detail::format_number(kMaxSize_m));
      }
      s.yaw_deg = r.number("yaw_deg", 0.0, -360.0, 360.0);
      break;
    }
    case SceneryKind::cylinder:
      s.centre = checked(r.vec3("centre", std::nullopt), r.path_of("centre"));
      s.radius_m = r.positive("radius_m", std::nullopt, kMaxSize_m);
      s.half_height_m = r.positive("half_height_m", std::nullopt, kMaxSize_m);
      break;
    case SceneryKind::mesh:
      s.vertices = read_vertices(r.raw("vertices"), r.path_of("vertices"));
      s.triangles = read_triangles(r.raw("triangles"), r.path_of("triangles"), s.vertices.size());
      break;
  }
  r.finish();
  return s;
}

SpawnShape read_shape(const nlohmann::json& j, const std::string& path) {
  FieldReader r(j, path);
  SpawnShape s;
  s.kind = read_kind(r, detail::kSpawnAreaKinds);
  switch (s.kind) {
    case SpawnAreaKind::disk:
      s.centre = checked(r.vec2("centre", std::nullopt), r.path_of("centre"));
      s.radius_m = r.number("radius_m", std::nullopt, 0.0, kMaxSize_m);
      break;
    case SpawnAreaKind::rect:
      s.centre = checked(r.vec2("centre", std::nullopt), r.path_of("centre"));
      s.half_extents_m = r.vec2("half_extents_m", std::nullopt);
      if (s.half_extents_m.x < 0.0) throw SceneError(r.path_of("half_extents_m") + "[0]", "must be >= 0");
      if (s.half_extents_m.y < 0.0) throw SceneError(r.path_of("half_extents_m") + "[1]", "must be >= 0");
      if (s.half_extents_m.x > kMaxSize_m || s.half_extents_m.y > kMaxSize_m)
        throw SceneError(r.path_of("half_extents_m"), "must be <= " + detail::format_number(kMaxSize_m));
      s.yaw_deg = r.number("yaw_deg", 0.0, -360.0, 360.0);
      break;
    case SpawnAreaKind::point:
      s.centre = checked(r.vec2("centre", std::nullopt), r.path_of("centre"));
      break;
    case SpawnAreaKind::line:
      s.from = checked(r.vec2("from", std::nullopt), r.path_of("from"));
      s.to = checked(r.vec2("to", std::nullopt), r.path_of("to"));
      break;
  }
  r.finish();
  return s;
}

Behavior read_behavior(const nlohmann::json& j, const std::string& path) {
  FieldReader r(j, path);
  Behavior b;
  b.kind = read_kind(r, detail::kBehaviourKinds);
  switch (b.kind) {
    case BehaviorKind::idle:
      break;
    case BehaviorKind::seek_point:
      b.target = checked(r.vec2("target", std::nullopt), r.path_of("target"));
      b.has_target = true;
      b.speed_mps = r.number("speed_mps", std::nullopt, 0.0, kMaxSpeed_mps);
      break;
    case BehaviorKind::march: {
      const bool has_dir = r.has("direction");
      b.has_target = r.has("target");
      if (has_dir == b.has_target) throw SceneError(path, "march needs exactly one of 'direction' or 'target'");
      if (b.has_target) {
        b.target = checked(r.vec2("target", std::nullopt), r.path_of("target"));
      } else {
        b.direction = r.vec2("direction", std::nullopt);
        if (b.direction.x == 0.0 && b.direction.y == 0.0) throw SceneError(r.path_of("direction"), "must not be zero");
      }
      b.speed_mps = r.number("speed_mps", std::nullopt, 0.0, kMaxSpeed_mps);
      break;
    }
  }
  r.finish();
  return b;
}

SpawnGroup read_spawn(const nlohmann::json& j, const std::string& path) {
  FieldReader r(j, path);
  SpawnGroup g;
  g.name = r.string("name", "");
  g.count = static_cast<std::uint32_t>(r.integer("count", std::nullopt, ObjectId::kMaxIndex));
  const auto* shape = r.raw("shape");
  if (!shape) throw SceneError(r.path_of("shape"), "is required");
  g.shape = read_shape(*shape, r.path_of("shape"));
  g.radius_m = r.positive("radius_m", g.radius_m, kMaxBodyRadius_m);
  g.half_height_m = r.number("half_height_m", g.half_height_m, 0.0, kMaxBodyRadius_m);
  g.archetype = r.string("archetype", g.archetype);
  if (r.has("faction")) g.faction = static_cast<std::uint32_t>(r.integer("faction", std::nullopt, params::kMaxFaction));
  if (r.has("group")) g.group = static_cast<std::uint32_t>(r.integer("group", std::nullopt, params::kMaxGroupId));
  if (r.has("z_m")) g.z_m = r.number("z_m", std::nullopt, -kMaxCoord_m, kMaxCoord_m);
  g.grounded = r.boolean("grounded", true);
  g.collision_id = static_cast<std::uint32_t>(r.integer("collision_id", 0, std::numeric_limits<std::uint32_t>::max()));
  if (const auto* b = r.raw("behaviour")) g.behavior = read_behavior(*b, r.path_of("behaviour"));
  if (const auto* p = r.raw("params")) g.params = detail::read_param_overrides(*p, r.path_of("params"));
  r.finish();
  return g;
}

const nlohmann::json& array_or_empty(const nlohmann::json* j, const std::string& path) {
  static const nlohmann::json kEmpty = nlohmann::json::array();
  if (!j) return kEmpty;
  if (!j->is_array()) throw SceneError(path, "must be an array");
  return *j;
}

}  // namespace

SceneDef scene_from_json(const nlohmann::json& doc, const std::string& base_dir) {
  FieldReader r(doc, "");
  SceneDef s;
  const auto version = r.integer("version", kSceneFormatVersion, 1000);
  if (version != kSceneFormatVersion)
    throw SceneError("version", "unsupported scene format version " + std::to_string(version) + " (this build reads " +
                                    std::to_string(kSceneFormatVersion) + ")");
  s.name = r.string("name", "");
  s.description = r.string("description", "");
  s.ticks = r.integer("ticks", s.ticks, 100'000'000);
  s.seed = r.integer("seed", s.seed, std::numeric_limits<std::uint64_t>::max());
  s.scale_scenery = r.boolean("scale_scenery", s.scale_scenery);
  if (const auto* j = r.raw("settings")) s.settings = read_settings(*j, "settings");
  s.params = read_source(r.raw("params"), "params", base_dir);
  s.policy = read_source(r.raw("policy"), "policy", base_dir);
  const auto& scenery = array_or_empty(r.raw("scenery"), "scenery");
  for (std::size_t i = 0; i < scenery.size(); ++i) s.scenery.push_back(read_scenery(scenery[i], item_path("scenery", i)));
  const auto& spawns = array_or_empty(r.raw("spawns"), "spawns");
  for (std::size_t i = 0; i < spawns.size(); ++i) s.spawns.push_back(read_spawn(spawns[i], item_path("spawns", i)));
  r.finish();
  if (s.agent_count() > ObjectId::kMaxIndex)
    throw SceneError("spawns", "total count " + std::to_string(s.agent_count()) + " exceeds the world's limit of " +
                                   std::to_string(ObjectId::kMaxIndex));
  return s;
}

SceneDef load_scene_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw SceneError("", "cannot open scene file '" + path + "'");
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::exception& e) {
    throw SceneError("", "scene file '" + path + "' is not valid JSON: " + e.what());
  }
  return scene_from_json(doc, std::filesystem::absolute(path).parent_path().string());
}

}  // namespace throng::scene
