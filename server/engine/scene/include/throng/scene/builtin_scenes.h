#pragma once
// Built-in scenes: the standard scenarios of the bench, the tests and (battle) the server's default.
// They live in code so nothing has to be installed to run them; each can be dumped to JSON
// (throng-bench --dump-scene NAME) and the dump reloads to the same world.
//
//   crush      20,000 spheres (r 0.35) uniform in a disk of radius 0.5 * sqrt(N), all seeking the
//              centre at 1.5 m/s, 60 Hz, 300 ticks: the dense-crowd benchmark.
//   street     two armies (factions 1 and 2) marching at each other down a street between two
//              long walls.
//   obstacles  a crowd pressing through a field of pillars, crates and soft bushes into a walled pen.
//   mixed      foot (light and heavy), cavalry and giants mixed in one disk, converging.
//   one_cell   every body starts at one point: the broadphase worst case (bodies idle).
//   battle     the default battle: two factions of a few thousand NPCs, ruined walls, bushes.
//
// A size other than the default is made with scale_scene (scale.h), like any scene file.
#include <string>
#include <vector>

#include "throng/scene/scene_def.h"

namespace throng::scene {

std::vector<std::string> builtin_scene_names();
bool is_builtin_scene(const std::string& name);

// The scene at its default size; throws SceneError naming the known scenes for an unknown name.
SceneDef builtin_scene(const std::string& name);

// A built-in name or a scene file path (built-in names win; a file named like a built-in can be
// given as ./crush).
SceneDef load_scene(const std::string& name_or_file);

}  // namespace throng::scene
