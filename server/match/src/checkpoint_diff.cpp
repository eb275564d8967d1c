// diff_checkpoints: check both headers, then compare the world sections body by body.
#include "throng/match/checkpoint_diff.h"

#include <string>

#include "throng/match/match.h"

namespace throng::match {
namespace {

// The world section of a match checkpoint (any version this build reads).
std::span<const std::uint8_t> world_section(std::span<const std::uint8_t> bytes, const char* which) {
  try {
    return checkpoint_sections(bytes).world;
  } catch (const CheckpointError& e) {
    throw CheckpointError(std::string(which) + ": " + e.what());
  }
}

}  // namespace

std::vector<BodyDifference> diff_checkpoints(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b,
                                             std::size_t max) {
  return diff_world_states(world_section(a, "first"), world_section(b, "second"), max);
}

}  // namespace throng::match
