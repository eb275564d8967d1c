#pragma once
// The WorldSettings fields with their valid ranges, one row each: WorldSettings::validate() checks
// them, and the scene parser, writer and SceneDef::operator== (a scene file can set each one)
// read and write them. A new setting is one line here, at the end of the table (extra_iterations is
// declared beside iterations, but its row came last). The rows' order feeds the world
// checkpoint's config hash (World::Impl::config_hash): reordering rows makes earlier checkpoints
// and match logs unreadable (WorldCheckpoint.ConfigHashOfFixedSettingsIsPinned).
#include <array>
#include <cstdint>

#include "throng/world/world_settings.h"

namespace throng::detail {

struct SettingField {
  enum class Type : std::uint8_t { f64, u32, boolean };
  const char* key;
  Type type;
  double WorldSettings::*f64 = nullptr;
  std::uint32_t WorldSettings::*u32 = nullptr;
  bool WorldSettings::*boolean = nullptr;
  double min = 0.0;
  double max = 0.0;
};

constexpr SettingField real(const char* key, double WorldSettings::*m, double lo, double hi) {
  return {key, SettingField::Type::f64, m, nullptr, nullptr, lo, hi};
}
constexpr SettingField whole(const char* key, std::uint32_t WorldSettings::*m, double lo, double hi) {
  return {key, SettingField::Type::u32, nullptr, m, nullptr, lo, hi};
}
constexpr SettingField flag(const char* key, bool WorldSettings::*m) {
  return {key, SettingField::Type::boolean, nullptr, nullptr, m, 0.0, 1.0};
}

inline constexpr std::array kSettingFields{
    real("dt_s", &WorldSettings::dt_s, 1e-4, 1.0),
    whole("iterations", &WorldSettings::iterations, 1, 256),
    real("contact_margin_m", &WorldSettings::contact_margin_m, 0.0, 10.0),
    real("pair_list_skin_m", &WorldSettings::pair_list_skin_m, 0.0, 1.0),
    real("converged_pen_over_radius", &WorldSettings::converged_pen_over_radius, 0.0, 1.0),
    flag("record_push_events", &WorldSettings::record_push_events),
    flag("warm_start", &WorldSettings::warm_start),
    real("blocked_motion_carry", &WorldSettings::blocked_motion_carry, 0.0, 0.99),
    real("conflict_share_limit", &WorldSettings::conflict_share_limit, 0.0, 0.5),
    whole("max_candidates_per_body", &WorldSettings::max_candidates_per_body, 4, 4096),
    real("cell_size_m", &WorldSettings::cell_size_m, 0.0, 1000.0),
    real("morale_radius_m", &WorldSettings::morale_radius_m, 0.1, 1000.0),
    whole("morale_refresh_ticks", &WorldSettings::morale_refresh_ticks, 1, 3600),
    whole("extra_iterations", &WorldSettings::extra_iterations, 0, 256),
};

}  // namespace throng::detail
