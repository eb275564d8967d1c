#pragma once
// The names the scene file uses for enum values, in one table per enum so the parser and the
// writer cannot disagree.
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "throng/scene/scene_def.h"

namespace throng::scene::detail {

inline constexpr std::array<std::pair<SceneryKind, std::string_view>, 3> kSceneryKinds{{
    {SceneryKind::box, "box"}, {SceneryKind::cylinder, "cylinder"}, {SceneryKind::mesh, "mesh"}}};
inline constexpr std::array<std::pair<SpawnAreaKind, std::string_view>, 4> kSpawnAreaKinds{{
    {SpawnAreaKind::disk, "disk"}, {SpawnAreaKind::rect, "rect"}, {SpawnAreaKind::point, "point"}, {SpawnAreaKind::line, "line"}}};
inline constexpr std::array<std::pair<BehaviorKind, std::string_view>, 3> kBehaviourKinds{{
    {BehaviorKind::idle, "idle"}, {BehaviorKind::seek_point, "seek_point"}, {BehaviorKind::march, "march"}}};

template <typename E, std::size_t N>
std::string kind_name(const std::array<std::pair<E, std::string_view>, N>& table, E kind) {
  for (const auto& [k, n] : table)
    if (k == kind) return std::string(n);
  return "?";
}

template <typename E, std::size_t N>
std::optional<E> kind_from_name(const std::array<std::pair<E, std::string_view>, N>& table, const std::string& name) {
  for (const auto& [k, n] : table)
    if (n == name) return k;
  return std::nullopt;
}

template <typename E, std::size_t N>
std::string kind_list(const std::array<std::pair<E, std::string_view>, N>& table) {
  std::string out;
  for (const auto& [k, n] : table) out += (out.empty() ? "" : ", ") + std::string(n);
  return out;
}

}  // namespace throng::scene::detail
