#pragma once
// Private helpers for building error messages. Shortest round-trip formatting (std::to_chars) so
// a message shows exactly the value the user wrote (0.1, not 0.10000000000000001).
#include <charconv>
#include <cmath>
#include <string>

namespace throng::params::detail {

inline std::string format_number(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof(buf), v);
  return std::string(buf, res.ptr);
}

}  // namespace throng::params::detail
