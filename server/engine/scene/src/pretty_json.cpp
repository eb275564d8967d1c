#include "pretty_json.h"

namespace throng::scene::detail {
namespace {

// One-line form with a space after ',' and ':'; numbers and strings exactly as nlohmann writes
// them (shortest round-trip doubles, escaped strings).
std::string one_line(const nlohmann::ordered_json& j) {
  if (j.is_object()) {
    if (j.empty()) return "{}";
    std::string o = "{ ";
    bool first = true;
    for (auto it = j.begin(); it != j.end(); ++it) {
      o += (first ? "" : ", ") + nlohmann::ordered_json(it.key()).dump() + ": " + one_line(it.value());
      first = false;
    }
    return o + " }";
  }
  if (j.is_array()) {
    if (j.empty()) return "[]";
    std::string o = "[";
    for (std::size_t i = 0; i < j.size(); ++i) o += (i ? ", " : "") + one_line(j[i]);
    return o + "]";
  }
  return j.dump();
}

void write(const nlohmann::ordered_json& j, std::size_t indent, std::size_t used, std::size_t width, std::string& out) {
  const std::string flat = one_line(j);
  if (!j.is_structured() || j.empty() || used + flat.size() <= width) {
    out += flat;
    return;
  }
  const std::string pad(indent + 2, ' ');
  out += j.is_object() ? "{\n" : "[\n";
  std::size_t i = 0;
  for (auto it = j.begin(); it != j.end(); ++it, ++i) {
    out += pad;
    std::size_t col = pad.size();
    if (j.is_object()) {
      const std::string key = nlohmann::ordered_json(it.key()).dump() + ": ";
      out += key;
      col += key.size();
    }
    write(it.value(), indent + 2, col + 1, width, out);  // + 1 for the trailing comma
    out += i + 1 < j.size() ? ",\n" : "\n";
  }
  out += std::string(indent, ' ') + (j.is_object() ? "}" : "]");
}

}  // namespace

std::string pretty_json(const nlohmann::ordered_json& j, std::size_t width) {
  std::string out;
  write(j, 0, 0, width, out);
  return out;
}

}  // namespace throng::scene::detail
