#pragma once
// ObjectParams: one row of the patent's parameter table (FIG. 8) — every parameter the push policy
// may read for one collision body, keyed by (object id, collision id).
//
// Why a plain struct with public fields plus validated setters: the policy reads these fields when
// it (re)computes an object's push coefficients, so reading must be trivial; writes from the
// outside world (runtime parameter API, JSON) go through set(), which range-checks and names the
// field in its error. Code that writes fields directly can call validate() afterwards (the Jolt
// "settings struct" pattern). Ranges and units are listed once, in param_range() / object_params.cpp.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "throng/params/categories.h"

namespace throng::params {

// Every numeric parameter of ObjectParams, in the order of the table. Categorical ones take the
// numeric mapping from categories.h; booleans are 0/1; bit sets are integers in [0, 2^32 - 1].
// The names (param_name) are the JSON keys and the runtime API's field names.
enum class Param : std::uint8_t {
  kind,                   // Kind ordinal (categories.h)
  importance,             // 0..10, designer status (boss = 10)
  size_m,                 // body size (diameter), metres
  weight_kg,              // mass, kg; JSON also accepts a WeightClass name under "weight"
  equipment_level,        // 0..10, weapon / armour level
  softness,               // 0..1, only meaningful for fixed bodies; 0 = rigid (see soft_push.h)
  speed_mps,              // dynamic: current speed, m/s
  facing_yaw_rad,         // dynamic: facing as yaw about +z (0 = +x); stored as a unit xy vector
  fixed,                  // 0/1: a fixed body is never moved by a push
  faction,                // 0..255, 0 = neutral; ally/enemy is relative to the policy's home faction
  character_type,         // CharacterType ordinal
  height_above_ground_m,  // dynamic: height of the body's base above the ground, metres
  group_id,               // 0 = no group, else a key into the GroupTable
  camera_distance_m,      // dynamic: distance to the nearest viewing camera, metres (capped)
  hp,                     // hit points, >= 0
  level,                  // training / growth level, >= 0
  collision_group,        // pass-through bits: a and b collide only if (group_a & mask_b) && (group_b & mask_a)
  collision_mask,
};
inline constexpr std::size_t kParamCount = 18;

// A body with no camera near it reads this distance; also the maximum stored distance, so one body
// far from every camera cannot dominate a score more than a body 1 km away.
inline constexpr double kCameraDistanceCap_m = 1000.0;
// Group ids index a dense table (GroupTable); this bounds its size.
inline constexpr std::uint32_t kMaxGroupId = 65535;

struct ParamRange {
  double min;
  double max;
  bool integral;  // value must be a whole number (categories, ids, bits, booleans)
};

std::string_view param_name(Param p);
ParamRange param_range(Param p);
// nullopt for an unknown name. Accepts the canonical names plus the alias "weight" (= weight_kg).
std::optional<Param> try_parse_param(std::string_view name);
// Throws std::invalid_argument("unknown parameter 'x' (known: ...)").
Param parse_param(std::string_view name);
// Comma-separated canonical names, for error messages.
std::string param_names_list();

// Why the value is not acceptable for p (NaN, infinite, out of range, not a whole number), without
// the field name so callers can prefix their own path; nullopt if the value is fine.
std::optional<std::string> check_param_value(Param p, double value);

struct ObjectParams {
  // Identity: the patent keys the table by object id and by collision id (one object may carry
  // several collision bodies, e.g. rider and horse). Not parameters, so not in Param.
  std::uint32_t object_id = 0;
  std::uint32_t collision_id = 0;

  Kind kind = Kind::foot;
  double importance = 1.0;
  double size_m = 0.6;
  double weight_kg = 80.0;  // medium
  double equipment_level = 0.0;
  double softness = 0.0;
  double speed_mps = 0.0;
  // Facing kept as a unit vector (not an angle) because the pair-time "facing" term needs a dot
  // product with the contact direction, and cos/sin per contact would be the expensive part.
  double facing_x = 1.0;
  double facing_y = 0.0;
  bool fixed = false;
  std::uint8_t faction = 0;
  CharacterType character_type = CharacterType::npc;
  double height_above_ground_m = 0.0;
  std::uint32_t group_id = 0;
  double camera_distance_m = kCameraDistanceCap_m;
  double hp = 100.0;
  double level = 1.0;
  std::uint32_t collision_group = 1u;
  std::uint32_t collision_mask = 0xFFFFFFFFu;

  // Validated writes; throw std::invalid_argument whose message starts with the field name.
  void set(Param p, double value);
  void set(std::string_view field, double value);
  // Text form for the runtime API: category names for kind / weight / character_type,
  // true/false for fixed, otherwise a decimal number.
  void set(std::string_view field, std::string_view text);
  // Normalises (x, y); throws on non-finite or (near-)zero vectors.
  void set_facing(double x, double y);

  // The numeric value of p (categories as their ordinal, fixed as 0/1, facing as yaw).
  double get(Param p) const;

  // Throws std::invalid_argument naming the first field that is out of range.
  void validate() const;

  FactionRelation relation(std::uint32_t home_faction) const { return faction_relation(faction, home_faction); }
};

// The pass-through collision filter (same convention as Box2D's category/mask bits).
constexpr bool collision_filter_pass(std::uint32_t group_a, std::uint32_t mask_a, std::uint32_t group_b,
                                     std::uint32_t mask_b) {
  return (group_a & mask_b) != 0u && (group_b & mask_a) != 0u;
}
inline bool should_collide(const ObjectParams& a, const ObjectParams& b) {
  return collision_filter_pass(a.collision_group, a.collision_mask, b.collision_group, b.collision_mask);
}

}  // namespace throng::params
