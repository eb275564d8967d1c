// Scene files (scene_from_json: what --scene loads and every match log's header carries). Bad
// input throws SceneError naming the field. An accepted scene must survive its documented round
// trip: scene_from_json(scene_to_json(s)) == s. Input: JSON text.
#include <cstdint>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "throng/scene/scene_error.h"
#include "throng/scene/scene_json.h"

using namespace throng;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nlohmann::json doc = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (doc.is_discarded()) return 0;  // not JSON: load_scene_file reports that before scene_from_json
  scene::SceneDef s;
  try {
    s = scene::scene_from_json(doc);
  } catch (const scene::SceneError&) {
    return 0;
  }
  const scene::SceneDef again = scene::scene_from_json(nlohmann::json::parse(scene::scene_to_text(s)));
  if (!(again == s)) std::abort();
  return 0;
}
