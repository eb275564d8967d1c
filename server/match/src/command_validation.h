#pragma once
// The checks a Command must pass that depend only on the command itself and the config (ranges,
// finiteness, action bits). The client-dependent checks (unknown client, wrong entity, sequence,
// rate) are in match_commands.cpp, which also fixes the overall order: unknown_client,
// not_your_entity, then these, then stale/duplicate sequence, then rate_limited.
#include <optional>

#include "throng/match/match.h"
#include "throng/match/match_config.h"
#include "throng/protocol/messages.h"

namespace throng::match {

// Slack on the |move| <= 1 and |facing| <= pi limits: a client's float rounding must not reject
// an honest full-stick command.
inline constexpr double kMoveSlack = 1e-3;
inline constexpr double kFacingSlack = 1e-3;

// First failing check in the order non_finite, move, facing, camera, actions; nullopt if fine.
std::optional<RejectReason> check_command_fields(const protocol::Command& c, const MatchConfig& config);

// |move| clamped to 1 (a command inside the slack never gives more than full speed).
struct MoveVector {
  double x;
  double y;
};
MoveVector clamped_move(const protocol::Command& c);

}  // namespace throng::match
