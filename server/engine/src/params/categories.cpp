// Name <-> enum tables for the categorical parameters. Plain arrays indexed by the enum value:
// the tables are tiny, and a linear scan keeps parsing allocation-free and obviously deterministic.
#include "throng/params/categories.h"

#include <array>

namespace throng::params {
namespace {

constexpr std::array<std::string_view, kKindCount> kKindNames = {"scenery", "foot", "mount", "vehicle",
                                                                 "giant"};
constexpr std::array<std::string_view, kCharacterTypeCount> kCharacterTypeNames = {"player", "npc", "mount",
                                                                                   "prop"};
constexpr std::array<std::string_view, kWeightClassCount> kWeightClassNames = {"light", "medium", "heavy",
                                                                               "very_heavy"};
constexpr std::array<std::string_view, kFactionRelationCount> kFactionRelationNames = {"enemy", "neutral",
                                                                                       "ally"};

template <typename Enum, std::size_t N>
std::optional<Enum> find_name(const std::array<std::string_view, N>& names, std::string_view name) {
  for (std::size_t i = 0; i < N; ++i) {
    if (names[i] == name) return static_cast<Enum>(i);
  }
  return std::nullopt;
}

template <std::size_t N>
std::string_view at_or_unknown(const std::array<std::string_view, N>& names, std::size_t i) {
  return i < N ? names[i] : std::string_view("?");
}

}  // namespace

std::string_view kind_name(Kind k) { return at_or_unknown(kKindNames, static_cast<std::size_t>(k)); }
std::string_view character_type_name(CharacterType t) {
  return at_or_unknown(kCharacterTypeNames, static_cast<std::size_t>(t));
}
std::string_view weight_class_name(WeightClass c) {
  return at_or_unknown(kWeightClassNames, static_cast<std::size_t>(c));
}
std::string_view faction_relation_name(FactionRelation r) {
  return at_or_unknown(kFactionRelationNames, static_cast<std::size_t>(r));
}

std::optional<Kind> parse_kind(std::string_view name) { return find_name<Kind>(kKindNames, name); }
std::optional<CharacterType> parse_character_type(std::string_view name) {
  return find_name<CharacterType>(kCharacterTypeNames, name);
}
std::optional<WeightClass> parse_weight_class(std::string_view name) {
  return find_name<WeightClass>(kWeightClassNames, name);
}
std::optional<FactionRelation> parse_faction_relation(std::string_view name) {
  return find_name<FactionRelation>(kFactionRelationNames, name);
}

std::string_view kind_names_list() { return "scenery, foot, mount, vehicle, giant"; }
std::string_view character_type_names_list() { return "player, npc, mount, prop"; }
std::string_view weight_class_names_list() { return "light, medium, heavy, very_heavy"; }
std::string_view faction_relation_names_list() { return "enemy, neutral, ally"; }

}  // namespace throng::params
