#pragma once
// A short match recorded in-process for the log-mode tests: the battle scene scaled down, two
// clients that join and walk (so the log has players as well as NPCs), written through the same
// MatchLogWriter the server uses.
#include <cstdint>
#include <filesystem>

namespace throng::view::testing {

struct RecordedLog {
  std::uint64_t ticks = 0;
  std::uint32_t tick_hz = 0;
  std::size_t bodies = 0;  // bodies in the world at the last tick
};

RecordedLog record_log(const std::filesystem::path& path, std::uint64_t ticks = 600, std::uint64_t bodies = 150);

}  // namespace throng::view::testing
