#include "json_util.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "params/text_util.h"
#include "throng/params/config_error.h"

namespace throng::params::detail {

std::string key_path(const std::string& parent, std::string_view key) {
  return parent.empty() ? std::string(key) : parent + "." + std::string(key);
}

std::string index_path(const std::string& parent, std::size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

void fail(const std::string& path, const std::string& message) { throw ConfigError(path, message); }

bool is_comment_key(std::string_view key) { return !key.empty() && key.front() == '_'; }

const json& expect_object(const json& j, const std::string& path) {
  if (!j.is_object()) fail(path, std::string("expected an object, got ") + j.type_name());
  return j;
}

const json& expect_array(const json& j, const std::string& path) {
  if (!j.is_array()) fail(path, std::string("expected an array, got ") + j.type_name());
  return j;
}

void check_known_keys(const json& obj, const std::string& path, std::initializer_list<std::string_view> known) {
  for (const auto& item : obj.items()) {
    if (is_comment_key(item.key())) continue;
    bool ok = false;
    for (std::string_view k : known) ok = ok || k == item.key();
    if (!ok) {
      std::string list;
      for (std::string_view k : known) list += (list.empty() ? "" : ", ") + std::string(k);
      fail(key_path(path, item.key()), "unknown key (expected one of: " + list + ")");
    }
  }
}

double read_number(const json& j, const std::string& path) {
  if (!j.is_number()) fail(path, std::string("expected a number, got ") + j.type_name());
  const double v = j.get<double>();
  if (std::isnan(v)) fail(path, "NaN is not allowed");
  if (std::isinf(v)) fail(path, "infinite value is not allowed");
  return v;
}

double read_number_in(const json& j, const std::string& path, double lo, double hi) {
  const double v = read_number(j, path);
  if (v < lo || v > hi) {
    fail(path, format_number(v) + " is out of range [" + format_number(lo) + ", " + format_number(hi) + "]");
  }
  return v;
}

std::uint32_t read_uint(const json& j, const std::string& path, std::uint32_t lo, std::uint32_t hi) {
  const double v = read_number_in(j, path, lo, hi);
  if (std::floor(v) != v) fail(path, format_number(v) + " is not a whole number");
  return static_cast<std::uint32_t>(v);
}

bool read_bool(const json& j, const std::string& path) {
  if (!j.is_boolean()) fail(path, std::string("expected true or false, got ") + j.type_name());
  return j.get<bool>();
}

std::string read_string(const json& j, const std::string& path) {
  if (!j.is_string()) fail(path, std::string("expected a string, got ") + j.type_name());
  return j.get<std::string>();
}

void check_version(const json& doc, int supported) {
  if (!doc.contains("version")) return;
  const std::uint32_t v = read_uint(doc.at("version"), "version", 0, 1000000);
  if (v != static_cast<std::uint32_t>(supported)) {
    fail("version", "unsupported version " + std::to_string(v) + " (this build reads version " +
                        std::to_string(supported) + ")");
  }
}

json parse_json_text(std::string_view text, std::string_view source) {
  try {
    return json::parse(text.begin(), text.end());
  } catch (const json::exception& e) {  // parse_error, and out_of_range for a number that overflows (found by fuzzing)
    fail("", std::string(source) + ": malformed JSON: " + e.what());
  }
}

json read_json_file(const std::string& file_path) {
  std::ifstream in(file_path, std::ios::binary);
  if (!in) fail("", "cannot open '" + file_path + "'");
  std::ostringstream buf;
  buf << in.rdbuf();
  return parse_json_text(buf.str(), file_path);
}

}  // namespace throng::params::detail
