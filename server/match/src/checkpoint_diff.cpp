// diff_checkpoints: check both headers, then compare the world sections body by body.
#include "throng/match/checkpoint_diff.h"

#include <string>

namespace throng::match {
namespace {

// The world section of a match checkpoint (header layout: CHECKPOINT.md).
std::span<const std::uint8_t> world_section(std::span<const std::uint8_t> bytes, const char* which) {
  ByteReader r(bytes);
  if (r.get<std::uint32_t>("magic") != 0x4B434D54u) r.fail(std::string(which) + " is not a match checkpoint");
  const auto version = r.get<std::uint32_t>("version");
  if (version != 1) r.fail(std::string(which) + ": checkpoint version " + std::to_string(version) + ", expected 1");
  r.take(8 + 8 + 4 + 8, "header");
  const auto len = r.get<std::uint32_t>("world section length");
  return {r.take(len, "world section"), len};
}

}  // namespace

std::vector<BodyDifference> diff_checkpoints(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b,
                                             std::size_t max) {
  return diff_world_states(world_section(a, "first"), world_section(b, "second"), max);
}

}  // namespace throng::match
