#include "throng/scene/builtin_scenes.h"

#include <array>
#include <filesystem>
#include <utility>

#include "builtin_catalogue.h"
#include "throng/scene/scene_error.h"
#include "throng/scene/scene_json.h"

namespace throng::scene {
namespace {

using Maker = SceneDef (*)();
constexpr std::array<std::pair<const char*, Maker>, 6> kBuiltins{{
    {"crush", detail::crush_scene},
    {"street", detail::street_scene},
    {"obstacles", detail::obstacles_scene},
    {"mixed", detail::mixed_scene},
    {"one_cell", detail::one_cell_scene},
    {"battle", detail::battle_scene},
}};

}  // namespace

std::vector<std::string> builtin_scene_names() {
  std::vector<std::string> out;
  for (const auto& [name, make] : kBuiltins) out.emplace_back(name);
  return out;
}

bool is_builtin_scene(const std::string& name) {
  for (const auto& [n, make] : kBuiltins)
    if (name == n) return true;
  return false;
}

SceneDef builtin_scene(const std::string& name) {
  for (const auto& [n, make] : kBuiltins)
    if (name == n) return make();
  std::string known;
  for (const auto& n : builtin_scene_names()) known += (known.empty() ? "" : ", ") + n;
  throw SceneError("scene", "unknown built-in scene '" + name + "' (known: " + known + ")");
}

SceneDef load_scene(const std::string& name_or_file) {
  if (is_builtin_scene(name_or_file)) return builtin_scene(name_or_file);
  if (!std::filesystem::exists(name_or_file)) {
    std::string known;
    for (const auto& n : builtin_scene_names()) known += (known.empty() ? "" : ", ") + n;
    throw SceneError("scene", "'" + name_or_file + "' is neither a built-in scene (" + known + ") nor an existing file");
  }
  return load_scene_file(name_or_file);
}

}  // namespace throng::scene
