#include "throng/scene/build_scene.h"

#include <nlohmann/json.hpp>
#include <numbers>

#include "throng/params/config_error.h"
#include "throng/params/params_json.h"
#include "throng/scene/builtin_params.h"
#include "throng/scene/scene_error.h"
#include "throng/scene/spawn.h"

namespace throng::scene {
namespace {

std::string item(const char* array, std::size_t i) { return std::string(array) + "[" + std::to_string(i) + "]"; }

// Loads a params/policy document, turning the params library's errors into scene paths:
// an inline policy's "terms[2].scale" becomes "policy.terms[2].scale".
template <typename T, typename FromJson, typename FromFile, typename Builtin>
T load_source(const DocumentSource& src, const char* field, FromJson from_json, FromFile from_file, Builtin builtin) {
  try {
    if (!src.file.empty()) return from_file(src.file);
    if (!src.inline_json.empty()) return from_json(nlohmann::json::parse(src.inline_json));
    return builtin();
  } catch (const params::ConfigError& e) {
    if (!src.file.empty()) throw SceneError(field, "in '" + src.file + "': " + e.what());
    throw SceneError(e.path().empty() ? std::string(field) : std::string(field) + "." + e.path(), e.message());
  } catch (const nlohmann::json::exception& e) {  // inline text that is not JSON
    throw SceneError(field, std::string("inline document: ") + e.what());
  } catch (const std::invalid_argument& e) {
    throw SceneError(field, e.what());
  } catch (const std::runtime_error& e) {  // unreadable file
    throw SceneError(field, e.what());
  }
}

void check_archetype(const params::ParamTable& table, const std::string& name, const std::string& path) {
  if (table.find_archetype(name) != nullptr) return;
  std::string known;
  for (const auto& n : table.archetype_names()) known += (known.empty() ? "" : ", ") + n;
  throw SceneError(path, "unknown archetype '" + name + "' (known: " + known + ")");
}

// Parameter overrides resolved and checked before anything is created, so a bad name fails the
// load instead of half-building the world.
std::vector<std::pair<params::Param, double>> resolve_params(const std::map<std::string, double>& overrides,
                                                             const std::string& path) {
  std::vector<std::pair<params::Param, double>> out;
  for (const auto& [name, value] : overrides) {
    const auto p = params::try_parse_param(name);
    if (!p) throw SceneError(path + "." + name, "unknown parameter (known: " + params::param_names_list() + ")");
    if (auto why = params::check_param_value(*p, value)) throw SceneError(path + "." + name, *why);
    out.emplace_back(*p, value);
  }
  return out;
}

void add_scenery(BuiltScene& b, const params::ParamTable& table, const Scenery& s, const std::string& path) {
  check_archetype(table, s.archetype, path + ".archetype");
  const auto overrides = resolve_params(s.params, path + ".params");
  ObjectId id;
  try {
    switch (s.kind) {
      case SceneryKind::box:
        id = b.world.add_fixed_box(s.centre, s.half_extents_m, s.yaw_deg * (std::numbers::pi / 180.0), s.archetype);
        break;
      case SceneryKind::cylinder:
        id = b.world.add_fixed_cylinder(s.centre, s.radius_m, s.half_height_m, s.archetype);
        break;
      case SceneryKind::mesh:
        id = b.world.add_fixed_mesh(s.vertices, s.triangles, s.archetype);
        break;
    }
    for (const auto& [p, v] : overrides) b.world.set_param(id, p, v);
  } catch (const std::invalid_argument& e) {
    throw SceneError(path, e.what());
  }
  b.scenery_ids.push_back(id);
}

void add_spawn_group(BuiltScene& b, const params::ParamTable& table, const SceneDef& scene, std::size_t index) {
  const SpawnGroup& g = scene.spawns[index];
  const std::string path = item("spawns", index);
  check_archetype(table, g.archetype, path + ".archetype");
  auto overrides = resolve_params(g.params, path + ".params");
  // faction and group are parameters too; set first so "params" can still override them.
  if (g.group) overrides.insert(overrides.begin(), {params::Param::group_id, double(*g.group)});
  if (g.faction) overrides.insert(overrides.begin(), {params::Param::faction, double(*g.faction)});
  const std::uint32_t behavior = b.driver.add_behaviour(resolve_behavior(g.behavior, g.shape, path + ".behaviour"));
  BodyDef def;
  def.radius_m = g.radius_m;
  def.half_height_m = g.half_height_m;
  def.grounded = g.grounded;
  def.archetype = g.archetype;
  def.collision_id = g.collision_id;
  const double z = g.centre_z();
  try {
    for (const Vec2& p : spawn_positions(g.shape, g.count, group_seed(scene.seed, index))) {
      def.position = {p.x, p.y, z};
      const ObjectId id = b.world.create_body(def);
      for (const auto& [param, v] : overrides) b.world.set_param(id, param, v);
      b.driver.add_agent(id, behavior);
      b.body_ids.push_back(id);
    }
  } catch (const std::invalid_argument& e) {
    throw SceneError(path, e.what());
  }
}

}  // namespace

params::ParamTable load_param_table(const DocumentSource& source) {
  return load_source<params::ParamTable>(
      source, "params", [](const nlohmann::json& j) { return params::param_table_from_json(j); },
      [](const std::string& f) { return params::load_param_table(f); }, [] { return builtin_param_table(); });
}

params::PushPolicy load_push_policy(const DocumentSource& source) {
  return load_source<params::PushPolicy>(
      source, "policy", [](const nlohmann::json& j) { return params::push_policy_from_json(j); },
      [](const std::string& f) { return params::load_push_policy(f); }, [] { return builtin_push_policy(); });
}

BuiltScene build_scene(const SceneDef& scene) {
  const params::ParamTable table = load_param_table(scene.params);
  const params::PushPolicy policy = load_push_policy(scene.policy);
  std::optional<World> world;
  try {
    world.emplace(scene.settings, table, policy);
  } catch (const std::invalid_argument& e) {
    throw SceneError("settings", e.what());
  }
  BuiltScene b{std::move(*world), SceneDriver(scene.settings.dt_s), {}, {}};
  for (std::size_t i = 0; i < scene.scenery.size(); ++i) add_scenery(b, table, scene.scenery[i], item("scenery", i));
  for (std::size_t i = 0; i < scene.spawns.size(); ++i) add_spawn_group(b, table, scene, i);
  return b;
}

const StepStats& step_scene(BuiltScene& built) {
  built.driver.apply(built.world);
  return built.world.step();
}

}  // namespace throng::scene
