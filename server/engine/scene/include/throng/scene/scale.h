#pragma once
// --agents N: the same scene with N bodies at the same crowd density.
//
// Spawn counts are scaled proportionally (largest-remainder rounding, so they add up to exactly N
// and groups keep their ratios), and the horizontal layout is scaled by s = sqrt(N / old_total)
// about the origin: shape centres and sizes, scenery positions and horizontal sizes, mesh
// vertices, targets. Body sizes, heights and speeds are unchanged, so bodies per m^2 stay the
// same: it is the same map seen at a different zoom.
//
// A scene with "scale_scenery": false keeps its scenery as written: its obstacles are objects of
// a given size where the crowd meets them (a 0.5 m post at the goal), and scaling them would make
// a different scene (a 0.25 m post; pillars too close for a body to pass between). Its spawns and
// targets still scale about the origin.
//
// Two exceptions, both so that scaling does not change the physics of the scene:
//  - line shapes (1D ranks) keep their spacing: their length scales by s^2 (their midpoint by s).
//  - a box half extent or cylinder radius never shrinks below min(original, 0.25 m): a 0.5 m
//    wall scaled to 1,000 bodies must not become a 5 cm sheet that bodies tunnel through.
#include <cstdint>

#include "throng/scene/scene_def.h"

namespace throng::scene {

inline constexpr double kMinScaledScenery_m = 0.25;

// Throws SceneError when agents == 0 or the scene has no bodies to scale.
SceneDef scale_scene(const SceneDef& scene, std::uint64_t agents);

// Largest-remainder split of total in proportion to weights (ties to the lower index).
std::vector<std::uint32_t> proportional_counts(const std::vector<std::uint32_t>& weights, std::uint64_t total);

}  // namespace throng::scene
