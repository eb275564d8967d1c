#pragma once
// The parameter file and push-policy file formats (server/engine/data/FORMATS.md): JSON in,
// validated ParamTable / PushPolicy out. They live in throng::scene, beside the scene format
// that inlines them, so the engine core (world, params, geometry) has no JSON in its headers.
//
// Every function throws ConfigError naming the JSON path of the bad field ("archetypes.cavalry.
// weight_kg", "terms[2].scale"); malformed JSON is a ConfigError with an empty path naming the
// source.
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>

#include "throng/params/param_table.h"
#include "throng/params/push_policy.h"

namespace throng::params {

ParamTable param_table_from_json(const nlohmann::json& doc);
ParamTable parse_param_table(std::string_view json_text, std::string_view source_name = "<string>");
ParamTable load_param_table(const std::string& file_path);

PushPolicy push_policy_from_json(const nlohmann::json& doc);
PushPolicy parse_push_policy(std::string_view json_text, std::string_view source_name = "<string>");
PushPolicy load_push_policy(const std::string& file_path);

}  // namespace throng::params
