#pragma once
// Reads the fields of one JSON object with type, range and finiteness checks, and rejects keys it
// was never asked about. Every error names the full JSON path ("spawns[2].count: must be >= 0").
//
// Why "asked about" rather than a list of allowed keys: each accessor call registers its key, so
// the set of accepted keys is exactly the set of fields the parser reads — a new field cannot be
// parsed yet forgotten in an allow-list, and a field that belongs to another kind (a box's
// "radius_m") is reported as unknown instead of being silently ignored.
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "throng/core/vec3.h"
#include "throng/scene/scene_def.h"

namespace throng::scene::detail {

// Shortest round-trip text for a number in messages ("0.0001", "1e+06").
std::string format_number(double v);

class FieldReader {
 public:
  // Throws SceneError unless j is an object.
  FieldReader(const nlohmann::json& j, std::string path);

  bool has(const std::string& key);  // registers key as known
  std::string path_of(const std::string& key) const;

  double number(const std::string& key, std::optional<double> fallback, double min, double max);
  // A size: finite, > 0 and <= max ("must be > 0" names negative and zero sizes alike).
  double positive(const std::string& key, std::optional<double> fallback, double max);
  std::uint64_t integer(const std::string& key, std::optional<std::uint64_t> fallback, std::uint64_t max);
  bool boolean(const std::string& key, std::optional<bool> fallback);
  std::string string(const std::string& key, std::optional<std::string> fallback);
  Vec2 vec2(const std::string& key, std::optional<Vec2> fallback);
  Vec3 vec3(const std::string& key, std::optional<Vec3> fallback);
  // The raw value (nullptr when absent); the key is registered as known.
  const nlohmann::json* raw(const std::string& key);

  // Throws on the first key (in the object's sorted key order) that was never asked about.
  // Keys starting with '_' are comments and always allowed.
  void finish() const;

 private:
  const nlohmann::json* lookup(const std::string& key);
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

  const nlohmann::json& j_;
  std::string path_;
  std::set<std::string> known_;
};

// Checks a value that is a number and finite; path is used in the error.
double finite_number(const nlohmann::json& v, const std::string& path);

// "name: value" pairs of parameter overrides ({"softness": 0.6}); names are checked by the caller.
std::map<std::string, double> read_param_overrides(const nlohmann::json& j, const std::string& path);

}  // namespace throng::scene::detail
