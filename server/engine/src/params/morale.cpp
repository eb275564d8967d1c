#include "throng/params/morale.h"

#include <array>
#include <cmath>
#include <string>

#include "text_util.h"
#include "throng/params/config_error.h"

namespace throng::params {
namespace {

constexpr std::array<std::string_view, 3> kStateNames = {"low", "normal", "high"};

void check_in(double v, double lo, double hi, const char* field) {
  const std::string path = std::string("morale.") + field;
  if (std::isnan(v)) throw ConfigError(path, "NaN is not allowed");
  if (!(v >= lo && v <= hi)) {
    throw ConfigError(path, detail::format_number(v) + " is out of range [" + detail::format_number(lo) + ", " +
                                detail::format_number(hi) + "]");
  }
}

}  // namespace

std::string_view morale_state_name(MoraleState s) {
  const auto i = static_cast<std::size_t>(s);
  return i < kStateNames.size() ? kStateNames[i] : std::string_view("?");
}

std::optional<MoraleState> parse_morale_state(std::string_view name) {
  for (std::size_t i = 0; i < kStateNames.size(); ++i) {
    if (kStateNames[i] == name) return static_cast<MoraleState>(i);
  }
  return std::nullopt;
}

void MoraleConfig::validate() const {
  check_in(low_enter, 0.0, 1.0, "low_enter");
  check_in(low_exit, 0.0, 1.0, "low_exit");
  check_in(high_exit, 0.0, 1.0, "high_exit");
  check_in(high_enter, 0.0, 1.0, "high_enter");
  check_in(low_offset, -100.0, 100.0, "low_offset");
  check_in(high_offset, -100.0, 100.0, "high_offset");
  // Without these orderings the dead bands vanish (or invert) and the level can flicker.
  if (!(low_enter < low_exit)) {
    throw ConfigError("morale.low_exit", "must be greater than low_enter (" + detail::format_number(low_enter) + ")");
  }
  if (!(low_exit <= high_exit)) {
    throw ConfigError("morale.high_exit", "must be at least low_exit (" + detail::format_number(low_exit) + ")");
  }
  if (!(high_exit < high_enter)) {
    throw ConfigError("morale.high_enter",
                      "must be greater than high_exit (" + detail::format_number(high_exit) + ")");
  }
}

MoraleState update_morale(MoraleState current, std::uint32_t allies_near, std::uint32_t enemies_near,
                          const MoraleConfig& config) {
  const std::uint64_t total = std::uint64_t{allies_near} + std::uint64_t{enemies_near};
  if (total == 0 || total < config.min_nearby) return current;
  const double f = static_cast<double>(allies_near) / static_cast<double>(total);
  switch (current) {
    case MoraleState::low:
      if (f > config.high_enter) return MoraleState::high;
      return f > config.low_exit ? MoraleState::normal : MoraleState::low;
    case MoraleState::normal:
      if (f < config.low_enter) return MoraleState::low;
      return f > config.high_enter ? MoraleState::high : MoraleState::normal;
    case MoraleState::high:
      if (f < config.low_enter) return MoraleState::low;
      return f < config.high_exit ? MoraleState::normal : MoraleState::high;
  }
  return current;
}

}  // namespace throng::params
