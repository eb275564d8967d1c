#pragma once
// One function per built-in scene, each at its default size (catalogue in builtin_scenes.h).
#include "throng/scene/scene_def.h"

namespace throng::scene::detail {

SceneDef crush_scene();
SceneDef one_cell_scene();
SceneDef mixed_scene();
SceneDef street_scene();
SceneDef obstacles_scene();
SceneDef battle_scene();

}  // namespace throng::scene::detail
