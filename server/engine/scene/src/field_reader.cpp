#include "field_reader.h"

#include <charconv>
#include <cmath>

#include "throng/scene/scene_error.h"

namespace throng::scene::detail {

std::string format_number(double v) {
  char buf[64];
  auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

FieldReader::FieldReader(const nlohmann::json& j, std::string path) : j_(j), path_(std::move(path)) {
  if (!j_.is_object()) throw SceneError(path_, "must be an object");
}

std::string FieldReader::path_of(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

void FieldReader::fail(const std::string& key, const std::string& message) const {
  throw SceneError(path_of(key), message);
}

const nlohmann::json* FieldReader::lookup(const std::string& key) {
  known_.insert(key);
  auto it = j_.find(key);
  if (it == j_.end() || it->is_null()) return nullptr;  // null = "use the default", as in JSON APIs
  return &*it;
}

bool FieldReader::has(const std::string& key) { return lookup(key) != nullptr; }

const nlohmann::json* FieldReader::raw(const std::string& key) { return lookup(key); }

double finite_number(const nlohmann::json& v, const std::string& path) {
  if (!v.is_number()) throw SceneError(path, "must be a number");
  const double d = v.get<double>();
  // JSON text cannot hold NaN/Inf, but inline objects built in code can; a NaN that reaches the
  // world only shows up ticks later as a NaN crowd, so it is stopped here.
  if (!std::isfinite(d)) throw SceneError(path, "must be finite");
  return d;
}

double FieldReader::number(const std::string& key, std::optional<double> fallback, double min, double max) {
  const auto* v = lookup(key);
  if (!v) {
    if (!fallback) fail(key, "is required");
    return *fallback;
  }
  const double d = finite_number(*v, path_of(key));
  if (d < min) fail(key, "must be >= " + format_number(min));
  if (d > max) fail(key, "must be <= " + format_number(max));
  return d;
}

double FieldReader::positive(const std::string& key, std::optional<double> fallback, double max) {
  const auto* v = lookup(key);
  if (!v) {
    if (!fallback) fail(key, "is required");
    return *fallback;
  }
  const double d = finite_number(*v, path_of(key));
  if (!(d > 0.0)) fail(key, "must be > 0");
  if (d > max) fail(key, "must be <= " + format_number(max));
  return d;
}

std::uint64_t FieldReader::integer(const std::string& key, std::optional<std::uint64_t> fallback,
                                   std::uint64_t max) {
  const auto* v = lookup(key);
  if (!v) {
    if (!fallback) fail(key, "is required");
    return *fallback;
  }
  // Parsed text gives unsigned for non-negative integers, but inline objects built in code
  // (json{{"count", 3}}) hold signed ones: accept both.
  if (v->is_number_integer()) {
    if (!v->is_number_unsigned() && v->get<std::int64_t>() < 0) fail(key, "must be >= 0");
    const auto u = v->get<std::uint64_t>();
    if (u > max) fail(key, "must be <= " + std::to_string(max));
    return u;
  }
  const double d = finite_number(*v, path_of(key));
  if (d < 0.0) fail(key, "must be >= 0");
  if (d != std::floor(d)) fail(key, "must be a whole number");
  if (d > static_cast<double>(max)) fail(key, "must be <= " + std::to_string(max));
  return static_cast<std::uint64_t>(d);
}

bool FieldReader::boolean(const std::string& key, std::optional<bool> fallback) {
  const auto* v = lookup(key);
  if (!v) {
    if (!fallback) fail(key, "is required");
    return *fallback;
  }
  if (!v->is_boolean()) fail(key, "must be true or false");
  return v->get<bool>();
}

std::string FieldReader::string(const std::string& key, std::optional<std::string> fallback) {
  const auto* v = lookup(key);
  if (!v) {
    if (!fallback) fail(key, "is required");
    return *fallback;
  }
  if (!v->is_string()) fail(key, "must be a string");
  return v->get<std::string>();
}

namespace {
template <std::size_t N>
std::array<double, N> read_array(const nlohmann::json& v, const std::string& path) {
  if (!v.is_array() || v.size() != N) throw SceneError(path, "must be an array of " + std::to_string(N) + " numbers");
  std::array<double, N> out{};
  for (std::size_t i = 0; i < N; ++i) out[i] = finite_number(v[i], path + "[" + std::to_string(i) + "]");
  return out;
}
}  // namespace

Vec2 FieldReader::vec2(const std::string& key, std::optional<Vec2> fallback) {
  const auto* v = lookup(key);
  if (!v) {
    if (!fallback) fail(key, "is required");
    return *fallback;
  }
  const auto a = read_array<2>(*v, path_of(key));
  return {a[0], a[1]};
}

Vec3 FieldReader::vec3(const std::string& key, std::optional<Vec3> fallback) {
  const auto* v = lookup(key);
  if (!v) {
    if (!fallback) fail(key, "is required");
    return *fallback;
  }
  const auto a = read_array<3>(*v, path_of(key));
  return {a[0], a[1], a[2]};
}

void FieldReader::finish() const {
  for (auto it = j_.begin(); it != j_.end(); ++it) {
    // "_comment", "_why": notes for humans, as in the parameter and policy files.
    if (!it.key().empty() && it.key()[0] == '_') continue;
    if (known_.count(it.key()) == 0) {
      std::string allowed;
      for (const auto& k : known_) allowed += (allowed.empty() ? "" : ", ") + k;
      fail(it.key(), "unknown key (allowed here: " + allowed + ")");
    }
  }
}

std::map<std::string, double> read_param_overrides(const nlohmann::json& j, const std::string& path) {
  if (!j.is_object()) throw SceneError(path, "must be an object of parameter name -> number");
  std::map<std::string, double> out;
  for (auto it = j.begin(); it != j.end(); ++it) out[it.key()] = finite_number(it.value(), path + "." + it.key());
  return out;
}

}  // namespace throng::scene::detail
