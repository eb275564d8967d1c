#pragma once
// A version 1 match checkpoint made from a version 2 one, as earlier builds wrote them (logs of
// those builds hold such keyframes): server/match/src/CHECKPOINT.md, "Version 1". Shared by the
// match checkpoint tests and the matchlog keyframe tests.
#include <cstdint>
#include <cstring>
#include <vector>

#include "throng/core/byte_io.h"
#include "throng/match/match.h"
#include "throng/match/match_config.h"

namespace throng::test {

// A version 1 checkpoint made from a version 2 one (CHECKPOINT.md, "Version 1"): one config hash
// over the config fields and then the interest fields (FNV-1a over their bytes, in field order),
// no interest hash, and no length prefixes on the match and snapshot sections.
inline std::vector<std::uint8_t> as_version_1(const std::vector<std::uint8_t>& v2, const match::MatchConfig& c) {
  std::uint64_t h = 14695981039346656037ull;
  const auto add = [&h](const auto& v) {
    unsigned char b[sizeof v];
    std::memcpy(b, &v, sizeof v);
    for (unsigned char x : b) h = (h ^ x) * 1099511628211ull;
  };
  add(c.tick_hz); add(c.max_clients); add(c.client_timeout_s); add(c.max_commands_per_tick); add(c.player_speed_mps);
  add(c.npc_speed_mps); add(c.camera_limit_m); add(c.seed);
  add(c.interest.radius_m); add(c.interest.exit_hysteresis); add(c.interest.budget_bytes);
  add(c.interest.keepalive_ticks); add(c.interest.removed_repeat);
  const match::CheckpointSections s = match::checkpoint_sections(v2);
  std::vector<std::uint8_t> v1;
  ByteWriter w(v1);
  const auto bytes = [&w](const std::uint8_t* p, std::size_t n) {
    if (n > 0) std::memcpy(w.grow(n), p, n);
  };
  w.put(std::uint32_t{0x4B434D54});                 // magic
  w.put(std::uint32_t{1});                          // version
  bytes(v2.data() + 8, 8);                          // scene hash
  w.put(h);                                         // config hash, interest settings included
  bytes(v2.data() + 32, 12);                        // body count, tick
  w.put(static_cast<std::uint32_t>(s.world.size()));
  bytes(s.world.data(), s.world.size());
  bytes(s.match_state.data(), s.match_state.size());
  bytes(s.snapshot_baselines.data(), s.snapshot_baselines.size());
  w.finish();
  return v1;
}

}  // namespace throng::test
