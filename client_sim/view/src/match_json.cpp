// The "match" message for the page (see match_json.h).
#include "throng/view/match_json.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <nlohmann/json.hpp>

namespace throng::view {

namespace {

// Millimetres are plenty for drawing and keep the JSON short (floats would print 17 digits).
double mm(double v) { return std::isfinite(v) ? std::round(v * 1000.0) / 1000.0 : 0.0; }

const char* kind_name(protocol::ShapeKind k) {
  switch (k) {
    case protocol::ShapeKind::box: return "box";
    case protocol::ShapeKind::cylinder: return "cylinder";
    case protocol::ShapeKind::mesh: return "mesh";
  }
  return "unknown";
}

nlohmann::json scenery_json(const protocol::SceneryShape& s) {
  nlohmann::json j = {{"id", s.id},
                      {"kind", kind_name(s.kind)},
                      {"archetype", s.archetype},
                      {"softness", mm(s.softness)},
                      {"cx", mm(s.cx)},
                      {"cy", mm(s.cy)},
                      {"cz", mm(s.cz)}};
  switch (s.kind) {
    case protocol::ShapeKind::box:
      j["hx"] = mm(s.hx);
      j["hy"] = mm(s.hy);
      j["hz"] = mm(s.hz);
      j["yaw"] = mm(s.yaw_rad);
      break;
    case protocol::ShapeKind::cylinder:
      j["radius"] = mm(s.radius);
      j["half_height"] = mm(s.half_height);
      break;
    case protocol::ShapeKind::mesh: {
      // Only well-formed triangles: indices inside the vertex array.
      const std::size_t nv = s.vertices.size() / 3;
      std::vector<double> v;
      v.reserve(nv * 3);
      for (std::size_t i = 0; i < nv * 3; ++i) v.push_back(mm(s.vertices[i]));
      std::vector<std::uint32_t> t;
      for (std::size_t i = 0; i + 2 < s.triangles.size(); i += 3) {
        if (s.triangles[i] < nv && s.triangles[i + 1] < nv && s.triangles[i + 2] < nv)
          t.insert(t.end(), {s.triangles[i], s.triangles[i + 1], s.triangles[i + 2]});
      }
      j["vertices"] = std::move(v);
      j["triangles"] = std::move(t);
      break;
    }
  }
  return j;
}

}  // namespace

std::string match_info_json(const protocol::MatchInfo& m, std::string_view mode) {
  nlohmann::json j;
  j["type"] = "match";
  j["mode"] = mode;
  j["match_id"] = m.match_id;
  j["scene"] = m.scene_name;
  j["tick_hz"] = m.tick_hz;
  j["interest_radius_m"] = mm(m.interest_radius_m);
  j["ended"] = m.state == protocol::MatchState::ended;
  j["bounds"] = {mm(m.world_min_x), mm(m.world_min_y), mm(m.world_max_x), mm(m.world_max_y)};
  j["archetypes"] = m.archetypes;
  j["character_types"] = {"player", "npc", "mount", "prop"};  // params::CharacterType order
  nlohmann::json scenery = nlohmann::json::array();
  for (const auto& s : m.scenery) scenery.push_back(scenery_json(s));
  j["scenery"] = std::move(scenery);
  // Structure-of-arrays like the protocol (cut to the shortest array, as MatchView does).
  const auto& r = m.roster;
  const std::size_t n = std::min({r.id.size(), r.radius_mm.size(), r.half_height_mm.size(), r.faction.size(),
                                  r.character_type.size(), r.archetype.size()});
  std::vector<double> radius(n), half_height(n);
  for (std::size_t i = 0; i < n; ++i) {
    radius[i] = r.radius_mm[i] / 1000.0;
    half_height[i] = r.half_height_mm[i] / 1000.0;
  }
  auto first = [n](const auto& v) { return std::vector(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n)); };
  j["roster"] = {{"id", first(r.id)},
                 {"radius", radius},
                 {"half_height", half_height},
                 {"faction", first(r.faction)},
                 {"type", first(r.character_type)},
                 {"archetype", first(r.archetype)}};
  return j.dump();
}

}  // namespace throng::view
