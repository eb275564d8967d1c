#pragma once
// One resolved contact of a tick, as the publisher, the log and the viewer see it ("results as
// arrays, not callbacks"). share_a is the pair's own share, the fraction of a push that moves a
// (b moves 1 - share_a): the patent's ratio. Pushes a pair makes in conflict (a later push in the
// tick, or every push of a pair held by its neighbours, WorldSettings::conflict_share_limit) split
// at that share clamped into [limit, 1 - limit]; the event still carries the pair's own share.
// For a body against fixed scenery, b is the fixed object's id and share_a is 1 (or the soft share).
#include <cstdint>

#include "throng/core/object_id.h"

namespace throng {

struct PushEvent {
  ObjectId a;
  ObjectId b;
  float depth_m = 0.0f;   // penetration at the start of the solve (before the warm start)
  float share_a = 0.0f;
  float push_m = 0.0f;    // total push of the pair this tick
};

}  // namespace throng
