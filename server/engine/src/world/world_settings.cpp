#include "throng/world/world_settings.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "world/settings_fields.h"

namespace throng {
namespace {
void check(double v, double lo, double hi, const char* field) {
  if (!std::isfinite(v) || v < lo || v > hi) {
    throw std::invalid_argument(std::string("world settings: ") + field + " = " + std::to_string(v) +
                                " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
}
}  // namespace

void WorldSettings::validate() const {
  // The ranges live in one table (settings_fields.h), which scene files are checked against too.
  for (const detail::SettingField& f : detail::kSettingFields) {
    switch (f.type) {
      case detail::SettingField::Type::f64: check(this->*f.f64, f.min, f.max, f.key); break;
      case detail::SettingField::Type::u32: check(static_cast<double>(this->*f.u32), f.min, f.max, f.key); break;
      case detail::SettingField::Type::boolean: break;
    }
  }
  // Not in the table: a scene file does not choose the machine's threads (see world_settings.h).
  check(static_cast<double>(threads), 1.0, 64.0, "threads");
}

}  // namespace throng
