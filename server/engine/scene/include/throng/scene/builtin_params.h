#pragma once
// The parameter table and push policy a scene uses when it names none ("params"/"policy" absent).
//
// Why in code and not the default files in server/engine/data/: built-in scenes must run from any
// working directory with no files installed (the bench in CI, tests under sanitizers), and a
// dumped built-in must reload to the same world. A scene that wants the designers' tables names
// the file.
//
// Archetypes (size_m = 2 * the radius the built-in scenes give them):
//   infantry  foot, 80 kg          light   foot, 55 kg, equipment 1     heavy   foot, 140 kg, equipment 6
//   cavalry   mount, 500 kg        giant   giant, 3000 kg
//   wall      fixed scenery        bush    fixed, softness 0.6          cushion fixed, softness 0.9
// Groups 1..6 exist with neutral morale (the built-in battles' formations).
// Policy: the patent's ratio mode with one term, weight_kg / 100: an 80 kg soldier against a
// 500 kg horse is pushed e^(4.2) ~ 67 times as far as the horse.
#include "throng/params/param_table.h"
#include "throng/params/push_policy.h"

namespace throng::scene {

params::ParamTable builtin_param_table();
params::PushPolicy builtin_push_policy();

}  // namespace throng::scene
