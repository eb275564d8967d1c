#pragma once
// Which bodies differ between two world checkpoints (World::save_state) of the same world: what
// `verify` reports when a re-simulation diverges, so the first diverging objects can be named.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace throng {

struct BodyDifference {
  std::uint32_t object_id = 0;  // ObjectId value; 0 for state of the world itself (the pair list's counters)
  std::string what;             // e.g. "x 1.25 vs 1.2500001; params.weight_kg 80 vs 160"
};

// Bodies whose saved state differs (present in one only, position, velocities, push, size,
// grounded, coefficients, warm-start entries, any parameter, where a kept pair list was searched),
// ascending object id, at most `max`; differences of the world's own state come first, as id 0.
// When more than `max` differ, those kept are the world's own state, bodies present in one only
// or with a different size or parameter, then those whose position, velocities or push went
// furthest apart.
// Each argument is exactly one world section. Throws CheckpointError on bad bytes.
std::vector<BodyDifference> diff_world_states(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b,
                                              std::size_t max = 20);

}  // namespace throng
