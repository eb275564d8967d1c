#pragma once
// A version 1 match checkpoint made from a version 3 one (as_version_3 makes one), as earlier builds wrote them (logs of
// those builds hold such keyframes): server/match/src/CHECKPOINT.md, "Version 1". Shared by the
// match checkpoint tests and the matchlog keyframe tests.
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "throng/core/byte_io.h"
#include "throng/match/match.h"
#include "throng/match/match_config.h"
#include "throng/scene/scene_def.h"

namespace throng::test {

// The same state as the previous build saved it (version 3: the NPC AI with its ids), by restoring
// `newest` into a match of its scene and config and saving it again.
inline std::vector<std::uint8_t> as_version_3(const std::vector<std::uint8_t>& newest, const scene::SceneDef& scene,
                                              const match::MatchConfig& config) {
  match::Match m(scene, config, "v3");
  m.restore_checkpoint(newest);
  std::vector<std::uint8_t> v3;
  m.save_checkpoint(v3, match::SaveOptions{.snapshot_baselines = !match::checkpoint_sections(newest).snapshot_baselines.empty(),
                                           .format_version = 3});
  return v3;
}

// The match section of a version 3 checkpoint as version 2 wrote it (CHECKPOINT.md, "Version 2"):
// without the owners' trailer and the last reject counter (foreign_participant, which must be 0).
inline std::vector<std::uint8_t> match_section_v2(std::span<const std::uint8_t> m) {
  std::uint32_t n_reasons = 0, n_clients = 0;
  std::memcpy(&n_reasons, m.data() + 2, 4);
  std::memcpy(&n_clients, m.data() + m.size() - 4, 4);
  std::vector<std::uint8_t> out;
  out.reserve(m.size());
  // Byte loops rather than range inserts: GCC 12 reports a false array-bounds error on those.
  const auto append = [&out](const std::uint8_t* b, const std::uint8_t* e) {
    for (; b != e; ++b) out.push_back(*b);
  };
  const std::uint32_t fewer = n_reasons - 1;
  std::uint8_t count[4];
  std::memcpy(count, &fewer, 4);
  append(m.data(), m.data() + 2);
  append(count, count + 4);
  append(m.data() + 6, m.data() + 6 + 8 * fewer);
  append(m.data() + 6 + 8 * n_reasons, m.data() + m.size() - 4 - 12 * n_clients);
  return out;
}

// A version 1 checkpoint made from a version 3 one (CHECKPOINT.md, "Version 1"): one config hash
// over the config fields and then the interest fields (FNV-1a over their bytes, in field order),
// no interest hash, no length prefixes on the match and snapshot sections, and the match section
// as version 2 had it.
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
  const std::vector<std::uint8_t> match_v2 = match_section_v2(s.match_state);
  bytes(match_v2.data(), match_v2.size());
  bytes(s.snapshot_baselines.data(), s.snapshot_baselines.size());
  w.finish();
  return v1;
}

}  // namespace throng::test
