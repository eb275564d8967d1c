#pragma once
// JSON text that a human can read and diff: containers that fit within the width stay on one
// line ("centre": [0, 22, 1]), larger ones break one element per line. nlohmann's dump(2) puts
// every number of every vector on its own line, which makes a scene file 5x longer.
#include <string>

#include <nlohmann/json.hpp>

namespace throng::scene::detail {

std::string pretty_json(const nlohmann::ordered_json& j, std::size_t width);

}  // namespace throng::scene::detail
