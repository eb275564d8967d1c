#pragma once
// MatchLogReader: opens a match log, validates its header and every record, and hands out the
// complete ticks.
//
// Opening maps the file and checks it end to end (CRC of every record, every tick entry decoded,
// tick numbers consecutive, index records agreeing with the blocks they list). How it ends:
//   closed    end record present: the writer closed the log cleanly.
//   unclosed  ends exactly at a record boundary without an end record: the writer stopped between
//             two writes (killed, or still writing). Nothing is lost from what is in the file.
//   torn      the last record is incomplete or fails its CRC and nothing valid follows: the
//             writer was killed mid-write or the machine lost its last writes. Every complete
//             tick before it is kept; problem says "log ends mid-record at byte X after tick T".
//   corrupt   a record fails its CRC (or does not decode) and valid records follow it: damage in
//             the middle. Reading stops there, never skipping it silently; problem names the
//             offset and the last good tick.
// Header problems (not a Throng log, unsupported format version, truncated or corrupt header,
// a scene this build cannot load) throw LogError instead: there is nothing to read.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "throng/matchlog/format.h"
#include "throng/matchlog/log_header.h"
#include "throng/matchlog/tick_record.h"

namespace throng::matchlog {

enum class LogEnd : std::uint8_t { closed, unclosed, torn, corrupt };
const char* to_string(LogEnd e);

struct BlockInfo {
  std::uint64_t first_tick = 0;
  std::uint32_t tick_count = 0;
  std::uint64_t offset = 0;        // of the record's length field
  std::uint32_t record_bytes = 0;  // framed size
};

struct GapInfo {
  std::uint64_t first_tick = 0;  // ticks the writer dropped (its backlog exceeded its cap)
  std::uint64_t count = 0;
  std::uint64_t offset = 0;
};

struct KeyframeInfo {
  std::uint64_t tick = 0;          // the world after this tick (Match::save_checkpoint)
  std::uint64_t offset = 0;        // of the record's length field
  std::uint32_t record_bytes = 0;  // framed size
  std::uint32_t raw_size = 0;      // checkpoint bytes uncompressed
};

struct LogScan {
  std::uint64_t file_bytes = 0;
  std::uint64_t header_bytes = 0;       // preamble + header record
  std::uint64_t ticks = 0;              // complete ticks readable
  std::uint64_t first_tick = 0, last_tick = 0;  // of the readable ticks (0 when none)
  std::uint64_t tick_block_bytes = 0;   // framed tick-block records
  std::uint64_t raw_tick_bytes = 0;     // the same ticks uncompressed
  std::uint64_t index_records = 0;
  std::uint32_t format_version = 0;
  std::vector<KeyframeInfo> keyframes;  // in tick order (v2 logs)
  std::uint64_t keyframe_bytes = 0;     // framed keyframe records
  std::uint64_t keyframe_raw_bytes = 0; // their checkpoints uncompressed
  std::vector<BlockInfo> blocks;        // in tick order
  std::vector<GapInfo> gaps;
  std::uint64_t ticks_missing = 0;      // sum of gaps
  bool scene_hash_matches = true;       // the stored scene re-serialises to the stored hash in this build
  LogEnd end = LogEnd::unclosed;
  std::uint64_t damage_offset = 0;      // torn / corrupt: where the bad record starts
  std::uint64_t resumes_at = 0;         // corrupt: where the next valid record was found
  std::string problem;                  // one sentence; "" when closed cleanly
  // End record (closed logs)
  std::uint64_t end_last_tick = 0, end_ticks_written = 0, end_ticks_dropped = 0;
};

class MatchLogReader {
 public:
  explicit MatchLogReader(const std::string& path);  // throws LogError (see above)
  ~MatchLogReader();
  MatchLogReader(const MatchLogReader&) = delete;
  MatchLogReader& operator=(const MatchLogReader&) = delete;

  const std::string& path() const { return path_; }
  const LogHeader& header() const { return header_; }
  const LogScan& scan() const { return scan_; }

  // Sequential access to the complete ticks, in file order (a gap shows as a jump in tick number).
  void rewind();
  bool next(TickRecord& out);  // false after the last readable tick
  // Makes the next next() return the first readable tick >= tick: binary search over the blocks
  // (O(log n)), then decoding of that one block. False if there is no such tick.
  bool seek(std::uint64_t tick);
  // The block holding tick, or nullptr (binary search).
  const BlockInfo* find_block(std::uint64_t tick) const;

  // The last keyframe at or before tick, or nullptr (binary search over scan().keyframes).
  const KeyframeInfo* find_keyframe(std::uint64_t tick) const;
  // The checkpoint bytes of a keyframe (decompressed into out). Throws LogError on a keyframe that
  // does not inflate (its CRC matched, so this means a writer bug). Thread-safe (const).
  void read_keyframe(const KeyframeInfo& k, std::vector<std::uint8_t>& out) const;
  // Decodes scan().blocks[index] into raw (the concatenated tick entries). Thread-safe (const).
  void decode_block(std::size_t index, std::vector<std::uint8_t>& raw) const;

 private:
  struct Scan;  // the validating scan, record by record (reader_scan.cpp)
  void read_header();
  void scan_records();
  std::span<const std::uint8_t> bytes() const { return {data_, size_}; }

  std::string path_;
  const std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
  void* map_ = nullptr;
  LogHeader header_;
  LogScan scan_;
  // cursor
  std::size_t block_ = 0;
  std::vector<std::uint8_t> raw_;
  std::size_t raw_pos_ = 0;
  bool raw_loaded_ = false;
};

// An independent sequential cursor over a reader's ticks, so several threads can read one log at
// once (each with its own cursor; the reader itself is only read).
class TickCursor {
 public:
  explicit TickCursor(const MatchLogReader& reader) : r_(reader) {}
  // The next next() returns the first readable tick >= tick; false if there is none.
  bool seek(std::uint64_t tick);
  bool next(TickRecord& out);

 private:
  const MatchLogReader& r_;
  std::size_t block_ = 0;
  std::vector<std::uint8_t> raw_;
  std::size_t pos_ = 0;
  bool loaded_ = false;
};

// A log that starts from a checkpoint (MatchLogWriter::begin_from: a hot standby's) opens with a
// gap for ticks 1..T and the keyframe of tick T: T, the tick its re-simulation starts after. 0 for
// a log that starts before tick 1.
std::uint64_t start_keyframe_tick(const LogScan& s);
// The gaps that are holes in the match (not the start of a log that starts from a checkpoint).
std::span<const GapInfo> holes(const LogScan& s);

}  // namespace throng::matchlog
