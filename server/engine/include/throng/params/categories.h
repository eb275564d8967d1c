#pragma once
// Categorical parameters of the patent's table (FIG. 8) and their documented numeric mappings.
//
// Categories are stored as small enums so rule predicates can test them with one bit operation;
// whenever a category feeds the weighted score it goes through the numeric mapping below, which is
// part of the file format (FORMATS.md) and therefore must not be renumbered.
#include <cstdint>
#include <optional>
#include <string_view>

namespace throng::params {

// What the body is, ordered by bulk so the ordinal is a usable score input (larger = bulkier).
//   scenery = 0 (walls, bushes: usually fixed), foot = 1, mount = 2, vehicle = 3, giant = 4.
enum class Kind : std::uint8_t { scenery = 0, foot = 1, mount = 2, vehicle = 3, giant = 4 };
inline constexpr std::uint32_t kKindCount = 5;

// Who controls the body. The ordinal is only an identifier (it is not a score input):
//   player = 0, npc = 1, mount = 2 (a riderless mount), prop = 3 (not a character at all).
enum class CharacterType : std::uint8_t { player = 0, npc = 1, mount = 2, prop = 3 };
inline constexpr std::uint32_t kCharacterTypeCount = 4;

// The patent's weight categories. Weight is stored in kilograms so designers can also give an
// exact mass; a category is shorthand for the mass below.
enum class WeightClass : std::uint8_t { light = 0, medium = 1, heavy = 2, very_heavy = 3 };
inline constexpr std::uint32_t kWeightClassCount = 4;

constexpr double weight_class_kg(WeightClass c) {
  switch (c) {
    case WeightClass::light: return 50.0;
    case WeightClass::medium: return 80.0;
    case WeightClass::heavy: return 200.0;
    case WeightClass::very_heavy: return 600.0;
  }
  return 80.0;
}

// The heaviest class whose mass is <= weight_kg; anything lighter than "light" is still light.
constexpr WeightClass weight_class_of(double weight_kg) {
  if (weight_kg >= weight_class_kg(WeightClass::very_heavy)) return WeightClass::very_heavy;
  if (weight_kg >= weight_class_kg(WeightClass::heavy)) return WeightClass::heavy;
  if (weight_kg >= weight_class_kg(WeightClass::medium)) return WeightClass::medium;
  return WeightClass::light;
}

// Ally / enemy is not stored per object: it is the object's faction compared with the policy's
// configured home faction (the side the players fight for). Faction 0 is reserved for neutral
// bodies (scenery, wildlife), which are neither.
//   ally: faction == home_faction, neutral: faction == 0, enemy: any other faction.
// Score value: ally = +1, neutral = 0, enemy = -1.
enum class FactionRelation : std::uint8_t { enemy = 0, neutral = 1, ally = 2 };
inline constexpr std::uint32_t kFactionRelationCount = 3;
inline constexpr std::uint32_t kNeutralFaction = 0;
inline constexpr std::uint32_t kMaxFaction = 255;

constexpr FactionRelation faction_relation(std::uint32_t faction, std::uint32_t home_faction) {
  if (faction == kNeutralFaction) return FactionRelation::neutral;
  return faction == home_faction ? FactionRelation::ally : FactionRelation::enemy;
}

constexpr double faction_relation_value(FactionRelation r) {
  switch (r) {
    case FactionRelation::enemy: return -1.0;
    case FactionRelation::neutral: return 0.0;
    case FactionRelation::ally: return 1.0;
  }
  return 0.0;
}

std::string_view kind_name(Kind k);
std::string_view character_type_name(CharacterType t);
std::string_view weight_class_name(WeightClass c);
std::string_view faction_relation_name(FactionRelation r);

// Parsers return nullopt for unknown names so callers can build an error naming their own field.
std::optional<Kind> parse_kind(std::string_view name);
std::optional<CharacterType> parse_character_type(std::string_view name);
std::optional<WeightClass> parse_weight_class(std::string_view name);
std::optional<FactionRelation> parse_faction_relation(std::string_view name);

// Comma-separated lists of the accepted names, for error messages.
std::string_view kind_names_list();
std::string_view character_type_names_list();
std::string_view weight_class_names_list();
std::string_view faction_relation_names_list();

}  // namespace throng::params
