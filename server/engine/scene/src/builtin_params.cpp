#include "throng/scene/builtin_params.h"

namespace throng::scene {
namespace {

params::ObjectParams character(params::Kind kind, double size_m, double weight_kg, double equipment) {
  params::ObjectParams p;
  p.kind = kind;
  p.size_m = size_m;
  p.weight_kg = weight_kg;
  p.equipment_level = equipment;
  p.character_type = params::CharacterType::npc;
  return p;
}

params::ObjectParams scenery(double softness) {
  params::ObjectParams p;
  p.kind = params::Kind::scenery;
  p.character_type = params::CharacterType::prop;
  p.fixed = true;
  p.softness = softness;
  p.weight_kg = 1.0e6;  // irrelevant for a fixed body; set so listings do not show a soldier's mass
  return p;
}

}  // namespace

params::ParamTable builtin_param_table() {
  params::ParamTable t;
  t.set_archetype("infantry", character(params::Kind::foot, 0.7, 80.0, 2.0));
  t.set_archetype("light", character(params::Kind::foot, 0.7, 55.0, 1.0));
  t.set_archetype("heavy", character(params::Kind::foot, 0.7, 140.0, 6.0));
  t.set_archetype("cavalry", character(params::Kind::mount, 1.4, 500.0, 3.0));
  t.set_archetype("giant", character(params::Kind::giant, 2.8, 3000.0, 5.0));
  t.set_archetype("wall", scenery(0.0));
  t.set_archetype("bush", scenery(0.6));
  t.set_archetype("cushion", scenery(0.9));
  // The built-in scenes put their formations in groups 1..6 (street and battle); registering them
  // lets the World track their morale, like a designer's table would.
  for (std::uint32_t id = 1; id <= 6; ++id) t.groups().set(id, params::Group{});
  return t;
}

params::PushPolicy builtin_push_policy() {
  params::Term weight;
  weight.input = params::TermInput::weight_kg;
  weight.weight = 1.0;
  weight.scale = 100.0;
  return params::PushPolicy(params::PushMode::ratio, {weight}, {});
}

}  // namespace throng::scene
