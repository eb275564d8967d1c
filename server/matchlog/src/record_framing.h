#pragma once
// Record framing checks for readers (FORMAT.md "Record framing"): is there a whole, CRC-valid
// record at a position, and after damage, where does the next plausible one start.
#include <cstddef>
#include <cstdint>
#include <string>

namespace throng::matchlog::detail {

struct RecordCheck {
  bool ok = false;
  std::uint8_t type = 0;
  std::uint32_t length = 0;
  std::string why;  // when !ok
};

RecordCheck check_record(const std::uint8_t* data, std::size_t size, std::size_t pos);

// An index record's payload layout (FORMAT.md "Index"): previous index offset, final flag, block
// count and 20-byte block entries from byte 13, then (format version 2 on) a keyframe count and
// 16-byte keyframe entries from `keyframe_part`. `why` is set when the length disagrees.
struct IndexCounts {
  std::uint32_t blocks = 0, keyframes = 0;
  std::uint64_t keyframe_part = 0;  // offset of the keyframe entries
  std::string why;
};
IndexCounts index_counts(const std::uint8_t* payload, std::uint32_t length, std::uint32_t format_version);

// After damage at `from`: the offset of a valid record further on, 0 if there is none. Cheap
// field checks before the CRC keep this linear on garbage (a tick block must continue after
// last_tick, an index/end record can only point backwards).
std::size_t find_valid_record_after(const std::uint8_t* data, std::size_t size, std::size_t from, std::uint64_t last_tick);

}  // namespace throng::matchlog::detail
