#pragma once
// Shared helpers for the world tests: small parameter tables and policies built in code, so every
// expected value can be derived from the numbers written here.
#include <cmath>
#include <string>
#include <vector>

#include "throng/params/param_table.h"
#include "throng/params/push_policy.h"
#include "throng/world/world.h"

namespace throng::test {

inline params::ObjectParams archetype_with(double weight_kg, params::CharacterType type = params::CharacterType::npc) {
  params::ObjectParams p;
  p.weight_kg = weight_kg;
  p.character_type = type;
  p.faction = 1;
  return p;
}

// infantry 80 kg, light 50, heavy 200, player 80, npc_heavy 200, wall (rigid), bush (soft 0.6),
// ghost (pass-through: its own collision group, accepts nothing).
inline params::ParamTable test_table() {
  params::ParamTable t;
  t.set_archetype("infantry", archetype_with(80.0));
  t.set_archetype("light", archetype_with(50.0));
  t.set_archetype("heavy", archetype_with(200.0));
  t.set_archetype("player", archetype_with(80.0, params::CharacterType::player));
  t.set_archetype("npc_heavy", archetype_with(200.0));
  params::ObjectParams wall;
  wall.kind = params::Kind::scenery;
  wall.fixed = true;
  t.set_archetype("wall", wall);
  params::ObjectParams bush = wall;
  bush.softness = 0.6;
  t.set_archetype("bush", bush);
  params::ObjectParams ghost = archetype_with(80.0);
  ghost.collision_group = 2u;
  ghost.collision_mask = 0u;
  t.set_archetype("ghost", ghost);
  return t;
}

inline params::PushPolicy weight_policy(params::PushMode mode, double scale_kg, bool invert = false) {
  params::Term term;
  term.input = params::TermInput::weight_kg;
  term.weight = 1.0;
  term.scale = scale_kg;
  term.invert = invert;
  return params::PushPolicy(mode, {term}, {});
}

inline WorldSettings quiet_settings() {
  WorldSettings s;
  s.dt_s = 1.0 / 60.0;
  s.iterations = 16;
  s.converged_pen_over_radius = 0.0;
  return s;
}

inline ObjectId add_sphere(World& w, double x, double y, double r = 0.35, const std::string& archetype = "infantry") {
  BodyDef d;
  d.position = {x, y, r};
  d.radius_m = r;
  d.archetype = archetype;
  return w.create_body(d);
}

inline double distance_xy(const Vec3& a, const Vec3& b) { return std::hypot(b.x - a.x, b.y - a.y); }

// Every body walks towards the origin at 1 m/s (and stands once within 0.5 m of it): an open
// crowd that jams in the middle. Call before each step.
inline void steer_to_origin(World& w) {
  for (std::size_t k = 0; k < w.body_count(); ++k) {
    const double x = w.pos_x()[k], y = w.pos_y()[k], d = std::hypot(x, y);
    w.set_desired_velocity(w.id_at(k), d > 0.5 ? Vec3{-x / d, -y / d, 0.0} : Vec3{});
  }
}

}  // namespace throng::test
