#pragma once
// A scene as plain data: world settings, where the parameter table and push policy come from,
// fixed scenery, and spawn groups with the behavior the bench's driver gives them every tick.
//
// Scenes are data (not code) so that the bench, the tests and later the server and bots share the
// same scenarios, and a scenario can be tuned without a rebuild. The JSON format is documented in
// scene_json.h; built-in scenes (builtin_scenes.h) are just SceneDefs made in code. Horizontal
// positions are 2D (x, y); z is up. Angles are in degrees in the file (readable), converted to
// radians only when the World is built.
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "throng/core/vec3.h"
#include "throng/world/world_settings.h"

namespace throng::scene {

struct Vec2 {
  double x = 0.0;
  double y = 0.0;
  constexpr bool operator==(const Vec2&) const = default;
};

// Where a parameter table or a push policy comes from: a file, an inline JSON object, or (both
// empty) the engine's built-in defaults. Relative file paths are resolved against the scene file's
// folder when the scene is loaded, so a scene can ship next to its parameter files.
struct DocumentSource {
  std::string file;
  // The inline JSON object as compact text (nlohmann's dump(): keys sorted, numbers exact), empty
  // when unused. Text rather than a JSON value so that this header, which every user of a scene
  // or a match includes, does not bring the whole JSON library along; scene_json.h reads it.
  std::string inline_json;
  bool is_default() const { return file.empty() && inline_json.empty(); }
  bool operator==(const DocumentSource&) const = default;
};

enum class SceneryKind : std::uint8_t { box, cylinder, mesh };

// One fixed scenery object. Which fields are used depends on kind; the loader rejects fields that
// do not belong to the kind, so a typo cannot silently do nothing.
struct Scenery {
  SceneryKind kind = SceneryKind::box;
  std::string archetype = "wall";  // name in the parameter table ("wall", "bush", "cushion", ...)
  Vec3 centre;                     // box, cylinder
  Vec3 half_extents_m;             // box, in the box's own frame before yaw
  double yaw_deg = 0.0;            // box, rotation about +z
  double radius_m = 0.0;           // cylinder
  double half_height_m = 0.0;      // cylinder
  std::vector<Vec3> vertices;      // mesh
  std::vector<std::array<std::uint32_t, 3>> triangles;  // mesh
  // Per-object parameter overrides by parameter name, e.g. {"softness": 0.6} for a soft bush.
  // std::map: applied in name order, so the World sees the same call sequence every run.
  std::map<std::string, double> params;
  bool operator==(const Scenery&) const = default;
};

enum class SpawnAreaKind : std::uint8_t { disk, rect, point, line };

// Where a spawn group's bodies start (horizontal placement; z comes from the group).
struct SpawnShape {
  SpawnAreaKind kind = SpawnAreaKind::disk;
  Vec2 centre;               // disk, rect, point
  double radius_m = 0.0;     // disk: uniform in area
  Vec2 half_extents_m;       // rect: uniform in area
  double yaw_deg = 0.0;      // rect
  Vec2 from;                 // line: evenly spaced from..to
  Vec2 to;
  bool operator==(const SpawnShape&) const = default;
};

enum class BehaviorKind : std::uint8_t { idle, seek_point, march };

// What the SceneDriver does with a body each tick.
//  - idle: desired velocity 0 (the body only moves when pushed).
//  - seek_point: head for target at speed_mps, slowing so it stops on the target (speed capped at
//    distance / dt) — a crowd converging on a point.
//  - march: move in a fixed direction forever (never stops: armies keep pressing). The direction
//    is given, or taken from the spawn shape's centre towards target when the scene is built.
struct Behavior {
  BehaviorKind kind = BehaviorKind::idle;
  Vec2 target;                      // seek_point; march when has_target
  bool has_target = false;          // march: direction from target
  Vec2 direction;                   // march when !has_target (normalised when built)
  double speed_mps = 0.0;
  bool operator==(const Behavior&) const = default;
};

struct SpawnGroup {
  std::string name;                  // free text for reports
  std::uint32_t count = 0;
  SpawnShape shape;
  double radius_m = 0.35;
  double half_height_m = 0.0;        // 0 = sphere
  std::string archetype = "infantry";
  // Side and unit, written as the parameters "faction" (0 = neutral, 1..255) and "group_id"
  // (0 = none) after the body is created; absent = keep the archetype's value.
  std::optional<std::uint32_t> faction;
  std::optional<std::uint32_t> group;
  std::optional<double> z_m;         // body centre height; default: standing on z = 0
  bool grounded = true;
  std::uint32_t collision_id = 0;
  Behavior behavior;
  std::map<std::string, double> params;  // per-body parameter overrides by name
  bool operator==(const SpawnGroup&) const = default;

  // Centre height actually used: z_m, or feet on the ground plane z = 0.
  double centre_z() const { return z_m ? *z_m : radius_m + half_height_m; }
};

struct SceneDef {
  std::string name;
  std::string description;
  std::uint64_t ticks = 300;   // default run length (the bench's --ticks overrides)
  std::uint64_t seed = 1;      // spawn placement RNG
  // Whether --agents (scale_scene) scales the scenery with the crowd's area. false: the scenery
  // stays as written and only the spawns scale (their areas and centres, and the behaviours'
  // targets, as always), for scenes whose obstacles are objects of a given size where the crowd
  // meets them (a post at the goal, which stays on the goal only if the goal is the origin).
  bool scale_scenery = true;
  WorldSettings settings;
  DocumentSource params;       // parameter table
  DocumentSource policy;       // push policy
  std::vector<Scenery> scenery;
  std::vector<SpawnGroup> spawns;
  // Field by field, settings included (WorldSettings has no operator== of its own).
  bool operator==(const SceneDef& o) const;

  std::uint64_t agent_count() const {
    std::uint64_t n = 0;
    for (const auto& s : spawns) n += s.count;
    return n;
  }
};

}  // namespace throng::scene
