// SceneDef -> JSON, every field written so a dump documents itself and reloads to the same SceneDef.
// nlohmann writes doubles with the shortest text that parses back to the same bits, which is what
// makes "dump, reload, same state hash" hold.
#include "kind_names.h"
#include "throng/scene/scene_json.h"

namespace throng::scene {
namespace {

nlohmann::json vec(Vec2 v) { return nlohmann::json::array({v.x, v.y}); }
nlohmann::json vec(Vec3 v) { return nlohmann::json::array({v.x, v.y, v.z}); }

nlohmann::json source(const DocumentSource& s) {
  if (!s.file.empty()) return s.file;
  return s.inline_doc;  // null = defaults
}

nlohmann::json settings(const WorldSettings& s) {
  return {{"dt_s", s.dt_s},
          {"iterations", s.iterations},
          {"contact_margin_m", s.contact_margin_m},
          {"converged_pen_over_radius", s.converged_pen_over_radius},
          {"warm_start", s.warm_start},
          {"max_candidates_per_body", s.max_candidates_per_body},
          {"cell_size_m", s.cell_size_m},
          {"morale_radius_m", s.morale_radius_m},
          {"morale_refresh_ticks", s.morale_refresh_ticks}};
}

nlohmann::json params(const std::map<std::string, double>& p) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [k, v] : p) j[k] = v;
  return j;
}

nlohmann::json scenery(const Scenery& s) {
  nlohmann::json j = {{"type", detail::kind_name(detail::kSceneryKinds, s.kind)}, {"archetype", s.archetype}};
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
      j["vertices"] = nlohmann::json::array();
      for (const auto& v : s.vertices) j["vertices"].push_back(vec(v));
      j["triangles"] = nlohmann::json::array();
      for (const auto& t : s.triangles) j["triangles"].push_back({t[0], t[1], t[2]});
      break;
    }
  }
  if (!s.params.empty()) j["params"] = params(s.params);
  return j;
}

nlohmann::json shape(const SpawnShape& s) {
  nlohmann::json j = {{"type", detail::kind_name(detail::kShapeKinds, s.kind)}};
  switch (s.kind) {
    case ShapeKind::disk:
      j["centre"] = vec(s.centre);
      j["radius_m"] = s.radius_m;
      break;
    case ShapeKind::rect:
      j["centre"] = vec(s.centre);
      j["half_extents_m"] = vec(s.half_extents_m);
      j["yaw_deg"] = s.yaw_deg;
      break;
    case ShapeKind::point:
      j["centre"] = vec(s.centre);
      break;
    case ShapeKind::line:
      j["from"] = vec(s.from);
      j["to"] = vec(s.to);
      break;
  }
  return j;
}

nlohmann::json behaviour(const Behaviour& b) {
  nlohmann::json j = {{"type", detail::kind_name(detail::kBehaviourKinds, b.kind)}};
  switch (b.kind) {
    case BehaviourKind::idle:
      break;
    case BehaviourKind::seek_point:
      j["target"] = vec(b.target);
      j["speed_mps"] = b.speed_mps;
      break;
    case BehaviourKind::march:
      if (b.has_target)
        j["target"] = vec(b.target);
      else
        j["direction"] = vec(b.direction);
      j["speed_mps"] = b.speed_mps;
      break;
  }
  return j;
}

nlohmann::json spawn(const SpawnGroup& g) {
  nlohmann::json j = {{"name", g.name},
                      {"count", g.count},
                      {"shape", shape(g.shape)},
                      {"radius_m", g.radius_m},
                      {"half_height_m", g.half_height_m},
                      {"archetype", g.archetype},
                      {"grounded", g.grounded},
                      {"collision_id", g.collision_id},
                      {"behaviour", behaviour(g.behaviour)}};
  if (g.z_m) j["z_m"] = *g.z_m;
  if (g.faction) j["faction"] = *g.faction;
  if (g.group) j["group"] = *g.group;
  if (!g.params.empty()) j["params"] = params(g.params);
  return j;
}

}  // namespace

nlohmann::json scene_to_json(const SceneDef& s) {
  nlohmann::json j = {{"version", kSceneFormatVersion},
                      {"name", s.name},
                      {"description", s.description},
                      {"ticks", s.ticks},
                      {"seed", s.seed},
                      {"settings", settings(s.settings)},
                      {"params", source(s.params)},
                      {"policy", source(s.policy)}};
  j["scenery"] = nlohmann::json::array();
  for (const auto& x : s.scenery) j["scenery"].push_back(scenery(x));
  j["spawns"] = nlohmann::json::array();
  for (const auto& g : s.spawns) j["spawns"].push_back(spawn(g));
  return j;
}

}  // namespace throng::scene
