#include "command_validation.h"

#include <cmath>
#include <numbers>

namespace throng::match {

const char* to_string(RejectReason r) {
  switch (r) {
    case RejectReason::non_finite: return "non_finite";
    case RejectReason::move_out_of_range: return "move_out_of_range";
    case RejectReason::facing_out_of_range: return "facing_out_of_range";
    case RejectReason::camera_out_of_range: return "camera_out_of_range";
    case RejectReason::bad_actions: return "bad_actions";
    case RejectReason::unknown_client: return "unknown_client";
    case RejectReason::not_your_entity: return "not_your_entity";
    case RejectReason::stale_sequence: return "stale_sequence";
    case RejectReason::duplicate_sequence: return "duplicate_sequence";
    case RejectReason::rate_limited: return "rate_limited";
    case RejectReason::foreign_participant: return "foreign_participant";
    case RejectReason::count_: break;
  }
  return "unknown";
}

std::optional<RejectReason> check_command_fields(const protocol::Command& c, const MatchConfig& config) {
  const float floats[] = {c.move_x, c.move_y, c.facing_rad, c.camera_x, c.camera_y, c.camera_z};
  for (float f : floats) {
    if (!std::isfinite(f)) return RejectReason::non_finite;
  }
  const double mx = c.move_x;
  const double my = c.move_y;
  if (std::sqrt(mx * mx + my * my) > 1.0 + kMoveSlack) return RejectReason::move_out_of_range;
  if (std::abs(double(c.facing_rad)) > std::numbers::pi + kFacingSlack) return RejectReason::facing_out_of_range;
  const double limit = config.camera_limit_m;
  if (std::abs(double(c.camera_x)) > limit || std::abs(double(c.camera_y)) > limit ||
      std::abs(double(c.camera_z)) > limit) {
    return RejectReason::camera_out_of_range;
  }
  if ((c.actions & ~protocol::kKnownActions) != 0u) return RejectReason::bad_actions;
  return std::nullopt;
}

MoveVector clamped_move(const protocol::Command& c) {
  const double mx = c.move_x;
  const double my = c.move_y;
  const double len = std::sqrt(mx * mx + my * my);
  if (len > 1.0) return {mx / len, my / len};
  return {mx, my};
}

}  // namespace throng::match
