#pragma once
// The scene file format (JSON) and its loader / writer.
//
// A scene file is one object. Every key is optional unless marked (required); unknown keys are
// errors, so a typo never silently does nothing — except keys starting with '_' ("_comment",
// "_why"), which are notes for humans, as in the parameter and policy files. Lengths in metres,
// speeds in m/s, angles in degrees, z is up. Errors throw SceneError naming the JSON path
// ("spawns[2].count: must be >= 0"); NaN, infinities and negative or zero sizes are rejected.
//
// {
//   "version": 1,                      // format version; only 1 exists
//   "name": "street", "description": "two armies meet in a walled street",
//   "ticks": 300,                      // default run length
//   "seed": 1,                         // spawn placement RNG (mt19937_64; same seed = same scene)
//   "scale_scenery": true,             // --agents scales the scenery with the crowd (a map);
//                                      //   false: the scenery stays as written (a post at the goal)
//   "settings": {                      // WorldSettings: same names, units and ranges; the list
//                                      //   is src/world/settings_fields.h
//     "dt_s": 0.016666666666666666, "iterations": 8, "contact_margin_m": 0.05,
//     "pair_list_skin_m": 0.1, "converged_pen_over_radius": 0.0001, "record_push_events": true, "warm_start": true,
//     "blocked_motion_carry": 0.9, "max_candidates_per_body": 48, "cell_size_m": 0,
//     "morale_radius_m": 5, "morale_refresh_ticks": 15, "extra_iterations": 16 },
//   "params": "params.json",           // parameter table: file (relative to this file), inline
//   "policy": { ... },                 //   object, or absent/null for builtin_params.h; same for
//                                      //   the push policy (formats: server/engine/data/FORMATS.md)
//   "scenery": [                       // fixed objects; "archetype" names a parameter-table entry
//     { "type": "box", "archetype": "wall", "centre": [0, 6, 1], "half_extents_m": [60, 0.5, 1],
//       "yaw_deg": 0 },
//     { "type": "cylinder", "archetype": "bush", "centre": [3, 0, 0.5], "radius_m": 1.2,
//       "half_height_m": 0.5, "params": { "softness": 0.6 } },   // per-object parameter overrides
//     { "type": "mesh", "archetype": "wall", "vertices": [[0,0,0], [1,0,0], [0,1,0]],
//       "triangles": [[0, 1, 2]] } ],
//   "spawns": [                        // bodies, created group by group (ids in this order)
//     { "name": "red", "count": 500,                                   // count (required)
//       "shape": { "type": "rect", "centre": [-30, 0], "half_extents_m": [10, 5], "yaw_deg": 0 },
//       //  or { "type": "disk", "centre": [0, 0], "radius_m": 20 }   (uniform in area)
//       //  or { "type": "point", "centre": [0, 0] }                  (all at one point)
//       //  or { "type": "line", "from": [0, 0], "to": [10, 0] }      (evenly spaced)
//       "radius_m": 0.35, "half_height_m": 0.55, "archetype": "infantry",
//       "faction": 1, "group": 3,       // parameters faction (0 = neutral) and group_id; absent =
//                                      //   the archetype's value
//       "z_m": 0.9,                    // body centre height; default radius + half_height (on z=0)
//       "grounded": true, "collision_id": 0,
//       "params": { "weight_kg": 120 },  // per-body overrides, parameter names as in object_params.h
//       "behaviour": { "type": "march", "direction": [1, 0], "speed_mps": 1.2 } } ] }
//       //  or { "type": "march", "target": [30, 0], "speed_mps": 1.2 }  (direction from the
//       //       shape's centre to target; never stops)
//       //  or { "type": "seek_point", "target": [0, 0], "speed_mps": 1.5 } (stops on target)
//       //  or { "type": "idle" }      (the default)
//
// Archetype and parameter names are checked against the parameter table when the World is built
// (build_scene), because only then is the table known.
#include <string>

#include <nlohmann/json.hpp>

#include "throng/scene/scene_def.h"

namespace throng::scene {

inline constexpr int kSceneFormatVersion = 1;

// Parses a scene document. base_dir is the folder relative "params"/"policy" file paths are
// resolved against ("" = leave them as written).
SceneDef scene_from_json(const nlohmann::json& doc, const std::string& base_dir = "");

// Reads and parses a scene file; unreadable files and malformed JSON are SceneErrors too.
SceneDef load_scene_file(const std::string& path);

// Writes every field (defaults included), so a dumped scene documents itself and
// scene_from_json(scene_to_json(s)) == s, bit for bit. Ordered: keys appear in the order above.
nlohmann::ordered_json scene_to_json(const SceneDef& scene);

// scene_to_json as text for humans: one line per scenery object / spawn group where it fits in
// 100 columns, numbers in shortest round-trip form. What --dump-scene prints.
std::string scene_to_text(const SceneDef& scene);

}  // namespace throng::scene
