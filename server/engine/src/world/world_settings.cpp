#include "throng/world/world_settings.h"

#include <cmath>
#include <stdexcept>
#include <string>

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
  check(dt_s, 1e-4, 1.0, "dt_s");
  check(iterations, 1, 256, "iterations");
  check(contact_margin_m, 0.0, 10.0, "contact_margin_m");
  check(pair_list_skin_m, 0.0, 1.0, "pair_list_skin_m");
  check(converged_pen_over_radius, 0.0, 1.0, "converged_pen_over_radius");
  check(blocked_motion_carry, 0.0, 0.99, "blocked_motion_carry");
  check(conflict_share_limit, 0.0, 0.5, "conflict_share_limit");
  check(max_candidates_per_body, 4, 4096, "max_candidates_per_body");
  check(cell_size_m, 0.0, 1000.0, "cell_size_m");
  check(morale_radius_m, 0.1, 1000.0, "morale_radius_m");
  check(morale_refresh_ticks, 1, 3600, "morale_refresh_ticks");
}

}  // namespace throng
