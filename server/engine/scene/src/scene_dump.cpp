// SceneDef -> JSON, every field written so a dump documents itself and reloads to the same SceneDef.
// nlohmann writes doubles with the shortest text that parses back to the same bits, which is what
// makes "dump, reload, same state hash" hold.
#include "kind_names.h"
#include "pretty_json.h"
#include "world/settings_fields.h"
#include "throng/scene/scene_json.h"

namespace throng::scene {
namespace {

using Json = nlohmann::ordered_json;  // keys in the order written: type first, then the layout

Json vec(Vec2 v) { return Json::array({v.x, v.y}); }
Json vec(Vec3 v) { return Json::array({v.x, v.y, v.z}); }

Json source(const DocumentSource& s) {
  if (!s.file.empty()) return s.file;
  if (s.inline_json.empty()) return nullptr;  // the defaults
  return Json::parse(s.inline_json);
}

Json settings(const WorldSettings& s) {
  Json j = Json::object();
  for (const auto& f : throng::detail::kSettingFields) {
    switch (f.type) {
      case throng::detail::SettingField::Type::f64: j[f.key] = s.*f.f64; break;
      case throng::detail::SettingField::Type::u32: j[f.key] = s.*f.u32; break;
      case throng::detail::SettingField::Type::boolean: j[f.key] = s.*f.boolean; break;
    }
  }
  return j;
}

Json params(const std::map<std::string, double>& p) {
  Json j = Json::object();
  for (const auto& [k, v] : p) j[k] = v;
  return j;
}

Json scenery(const Scenery& s) {
  Json j = {{"type", detail::kind_name(detail::kSceneryKinds, s.kind)}, {"archetype", s.archetype}};
  switch (s.kind) {
    case SceneryKind::box:
      j["centre"] = vec(s.centre);
      j["half_extents_m"] = vec(s.half_extents_m);
      j["yaw_deg"] = s.yaw_deg;
      break;
    case SceneryKind::cylinder:
      j["centre"] = vec(s.centre);
      j["radius_m"] = s.radius_m;
      j["half_height_m"] = s.half_height_m;
      break;
    case SceneryKind::mesh: {
      j["vertices"] = Json::array();
      for (const auto& v : s.vertices) j["vertices"].push_back(vec(v));
      j["triangles"] = Json::array();
      for (const auto& t : s.triangles) j["triangles"].push_back({t[0], t[1], t[2]});
      break;
    }
  }
  if (!s.params.empty()) j["params"] = params(s.params);
  return j;
}

Json shape(const SpawnShape& s) {
  Json j = {{"type", detail::kind_name(detail::kSpawnAreaKinds, s.kind)}};
  switch (s.kind) {
    case SpawnAreaKind::disk:
      j["centre"] = vec(s.centre);
      j["radius_m"] = s.radius_m;
      break;
    case SpawnAreaKind::rect:
      j["centre"] = vec(s.centre);
      j["half_extents_m"] = vec(s.half_extents_m);
      j["yaw_deg"] = s.yaw_deg;
      break;
    case SpawnAreaKind::point:
      j["centre"] = vec(s.centre);
      break;
    case SpawnAreaKind::line:
      j["from"] = vec(s.from);
      j["to"] = vec(s.to);
      break;
  }
  return j;
}

Json behavior(const Behavior& b) {
  Json j = {{"type", detail::kind_name(detail::kBehaviourKinds, b.kind)}};
  switch (b.kind) {
    case BehaviorKind::idle:
      break;
    case BehaviorKind::seek_point:
      j["target"] = vec(b.target);
      j["speed_mps"] = b.speed_mps;
      break;
    case BehaviorKind::march:
      if (b.has_target)
        j["target"] = vec(b.target);
      else
        j["direction"] = vec(b.direction);
      j["speed_mps"] = b.speed_mps;
      break;
  }
  return j;
}

Json spawn(const SpawnGroup& g) {
  Json j;
  j["name"] = g.name;
  j["count"] = g.count;
  j["shape"] = shape(g.shape);
  j["radius_m"] = g.radius_m;
  j["half_height_m"] = g.half_height_m;
  j["archetype"] = g.archetype;
  if (g.faction) j["faction"] = *g.faction;
  if (g.group) j["group"] = *g.group;
  if (g.z_m) j["z_m"] = *g.z_m;
  j["grounded"] = g.grounded;
  j["collision_id"] = g.collision_id;
  if (!g.params.empty()) j["params"] = params(g.params);
  j["behaviour"] = behavior(g.behavior);
  return j;
}

}  // namespace

Json scene_to_json(const SceneDef& s) {
  Json j = {{"version", kSceneFormatVersion},
                      {"name", s.name},
                      {"description", s.description},
                      {"ticks", s.ticks},
                      {"seed", s.seed},
                      {"settings", settings(s.settings)},
                      {"params", source(s.params)},
                      {"policy", source(s.policy)}};
  // Written only when it differs from the default: the dumps of the built-ins stay as they were.
  if (!s.scale_scenery) j["scale_scenery"] = false;
  j["scenery"] = Json::array();
  for (const auto& x : s.scenery) j["scenery"].push_back(scenery(x));
  j["spawns"] = Json::array();
  for (const auto& g : s.spawns) j["spawns"].push_back(spawn(g));
  return j;
}

std::string scene_to_text(const SceneDef& scene) { return detail::pretty_json(scene_to_json(scene), 100) + "\n"; }

}  // namespace throng::scene
