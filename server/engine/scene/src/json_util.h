#pragma once
// Private helpers shared by the two JSON loaders: typed reads that fail with a ConfigError naming
// the JSON path, and strict key checking (an unknown key is almost always a typo, and a silently
// ignored typo in a balance file is a bug that takes days to find). Keys starting with '_' are
// comments and are skipped.
#include <cstdint>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace throng::params::detail {

using nlohmann::json;

std::string key_path(const std::string& parent, std::string_view key);
std::string index_path(const std::string& parent, std::size_t index);

[[noreturn]] void fail(const std::string& path, const std::string& message);

bool is_comment_key(std::string_view key);
const json& expect_object(const json& j, const std::string& path);
const json& expect_array(const json& j, const std::string& path);
// Throws for every key of `obj` that is neither in `known` nor a comment.
void check_known_keys(const json& obj, const std::string& path, std::initializer_list<std::string_view> known);

double read_number(const json& j, const std::string& path);  // finite numbers only
double read_number_in(const json& j, const std::string& path, double lo, double hi);
std::uint32_t read_uint(const json& j, const std::string& path, std::uint32_t lo, std::uint32_t hi);
bool read_bool(const json& j, const std::string& path);
std::string read_string(const json& j, const std::string& path);

// "version", if present, must equal `supported`.
void check_version(const json& doc, int supported);

// Parse text / a file; malformed JSON becomes a ConfigError with an empty path naming the source.
json parse_json_text(std::string_view text, std::string_view source);
json read_json_file(const std::string& file_path);

}  // namespace throng::params::detail
