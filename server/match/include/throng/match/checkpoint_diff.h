#pragma once
// Which objects differ between two checkpoints of the same match (Match::save_checkpoint): what
// `throng-replay verify` reports when a re-simulation diverges from the log's keyframe.
#include <cstdint>
#include <span>
#include <vector>

#include "throng/core/byte_io.h"
#include "throng/world/world_state_diff.h"

namespace throng::match {

// object_id = ObjectId value; what = the differing fields with both values, e.g.
// "x 1.25 vs 1.2500000000000002; params.weight_kg 80 vs 160".
using BodyDifference = throng::BodyDifference;

// Objects whose state differs between two checkpoints of the same match (at most `max`, in
// ascending object id; the furthest apart when more differ), for `verify` to say which objects
// diverged. Compares the world state of every body (pose, velocities, push, size, coefficients,
// warm start, every parameter). Throws CheckpointError on bad bytes.
std::vector<BodyDifference> diff_checkpoints(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b,
                                             std::size_t max = 20);

}  // namespace throng::match
