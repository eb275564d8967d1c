#pragma once
// Match-log format constants (the full description is server/matchlog/FORMAT.md).
//
//   file   = magic (8 bytes "\x89THRONG\n") | format version (u32 LE) | record*
//   record = [payload length u32 LE][type u8][payload][crc32c u32 LE over length, type, payload]
//
// The first record is always the header (JSON), then tick blocks, keyframes (v2), periodic index
// records, gap records if the writer ever had to drop ticks, and on a clean close a final index +
// end record.
#include <cstdint>
#include <stdexcept>
#include <string>

namespace throng::matchlog {

inline constexpr std::uint8_t kMagic[8] = {0x89, 'T', 'H', 'R', 'O', 'N', 'G', '\n'};
// 3: joins and commands carry their sender (the DDS participant), joins its authenticated identity.
inline constexpr std::uint32_t kFormatVersion = 3;   // what this build writes
inline constexpr std::uint32_t kOldestReadableFormatVersion = 1;  // v1: no keyframes (read too)
inline constexpr std::size_t kFilePreambleBytes = 12;  // magic + version
inline constexpr std::size_t kRecordOverheadBytes = 9;  // length + type + crc
// No record is larger (a tick block of 256 clients x 4 commands is ~50 KB per tick): a length
// above this is damage, not data.
inline constexpr std::uint32_t kMaxRecordPayload = 256u << 20;

enum class RecordType : std::uint8_t {
  header = 1,      // JSON text (LogHeader)
  tick_block = 2,  // consecutive ticks: inputs in applied order, flags, state hash
  index = 3,       // offsets of tick blocks (periodic, and one final index on close)
  gap = 4,         // ticks the writer had to drop (disk backlog over its hard cap)
  end = 5,         // clean close: offset of the final index, tick counts
  keyframe = 6,    // v2: Match::save_checkpoint() after a tick, zstd-compressed (for seeking)
};
const char* to_string(RecordType t);
bool is_known_record_type(std::uint8_t t);

// Per-tick flags.
inline constexpr std::uint8_t kTickShutdownBegan = 1u << 0;  // Match::begin_shutdown() was called before this tick
inline constexpr std::uint8_t kKnownTickFlags = kTickShutdownBegan;

// Gap record reasons.
inline constexpr std::uint8_t kGapDropped = 1;                // the writer's backlog exceeded its cap
inline constexpr std::uint8_t kGapStartedFromCheckpoint = 2;  // the log starts after these ticks (begin_from)

// Tick-block payload codecs.
enum class BlockCodec : std::uint8_t { raw = 0, zstd = 1 };

// Every problem opening or reading a log: the message is a full sentence for a human (it names
// the file offset where there is one).
class LogError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "throng 0.1.0 (git <describe>, compiled <date>)": what the writer stores when given no build id.
std::string default_build_id();

}  // namespace throng::matchlog
