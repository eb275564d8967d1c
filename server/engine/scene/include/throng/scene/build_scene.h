#pragma once
// SceneDef -> a ready World plus the driver that moves its bodies.
//
// Build order is part of the determinism contract: scenery in file order, then spawn groups in
// file order, bodies of a group in placement order; per-object parameters (faction, group,
// "params" overrides in name order) are set right after each object is created. The same SceneDef
// therefore gives the same ids, the same World call sequence and the same state hash.
#include <vector>

#include "throng/core/object_id.h"
#include "throng/params/param_table.h"
#include "throng/params/push_policy.h"
#include "throng/scene/scene_def.h"
#include "throng/scene/scene_driver.h"
#include "throng/world/world.h"

namespace throng::scene {

struct BuiltScene {
  World world;
  SceneDriver driver;
  std::vector<ObjectId> scenery_ids;  // scene.scenery order
  std::vector<ObjectId> body_ids;     // creation order
};

// The scene's parameter table / push policy: its file, its inline object, or the built-ins
// (builtin_params.h). Errors are SceneErrors under "params" / "policy".
params::ParamTable load_param_table(const DocumentSource& source);
params::PushPolicy load_push_policy(const DocumentSource& source);

// Throws SceneError naming the field for unknown archetypes / parameters and for anything the
// World rejects.
BuiltScene build_scene(const SceneDef& scene);

// Advances one tick the way the bench does: driver first (desired velocities), then World::step.
const StepStats& step_scene(BuiltScene& built);

}  // namespace throng::scene
