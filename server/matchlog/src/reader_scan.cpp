// The reader's validating scan: every record after the header checked (framing, CRC, then what
// each type must hold, in order), the blocks, keyframes and gaps listed, and the end classified
// as closed, unclosed, torn (a tail cut mid-record) or corrupt (damage with valid records after).
#include <algorithm>

#include <fmt/format.h>

#include "throng/core/byte_io.h"
#include "record_framing.h"
#include "throng/matchlog/reader.h"
#include "throng/matchlog/tick_record.h"

namespace throng::matchlog {


// One pass over the records. Each record type has its check; a check returns what is wrong with
// the record ("" when nothing), and the first problem ends the scan there.
struct MatchLogReader::Scan {
  MatchLogReader& reader;
  LogScan& s;
  std::size_t pos = 0;
  std::uint64_t expected = 1;  // next tick the file should hold
  std::uint64_t last_good_tick = 0;
  bool seen_end = false;
  std::uint64_t final_index_offset = 0;
  std::vector<std::uint8_t> raw;
  TickRecord scratch;

  explicit Scan(MatchLogReader& r) : reader(r), s(r.scan_), pos(r.scan_.header_bytes) {}

  void run();
  // A record that fails framing or its CRC: a torn tail when nothing valid follows (the scan ends
  // there, keeping every complete tick), else damage in the middle.
  void framing_failed(const detail::RecordCheck& r);
  std::string record(RecordType type, const std::uint8_t* p, std::uint32_t len, std::uint32_t framed);
  std::string tick_block(const std::uint8_t* p, std::uint32_t len, std::uint32_t framed);
  std::string gap(const std::uint8_t* p, std::uint32_t len);
  std::string keyframe(const std::uint8_t* p, std::uint32_t len, std::uint32_t framed);
  std::string index(const std::uint8_t* p, std::uint32_t len);
  std::string end_record(const std::uint8_t* p, std::uint32_t len);
  void finish();
};

void MatchLogReader::scan_records() { Scan(*this).run(); }

void MatchLogReader::Scan::run() {
  while (pos < reader.size_) {
    const detail::RecordCheck r = detail::check_record(reader.data_, reader.size_, pos);
    if (!r.ok) {
      framing_failed(r);
      return;
    }
    const std::uint32_t framed = r.length + static_cast<std::uint32_t>(kRecordOverheadBytes);
    const auto type = static_cast<RecordType>(r.type);
    const std::string damage = record(type, reader.data_ + pos + 5, r.length, framed);
    if (!damage.empty()) {
      s.end = LogEnd::corrupt;
      s.damage_offset = pos;
      s.problem = fmt::format("corrupt {} record at byte {} after tick {}: {}; reading stops at tick {}", to_string(type),
                              pos, last_good_tick, damage, last_good_tick);
      return;
    }
    pos += framed;
  }
  finish();
}

void MatchLogReader::Scan::framing_failed(const detail::RecordCheck& r) {
  const std::size_t next = detail::find_valid_record_after(reader.data_, reader.size_, pos, last_good_tick);
  s.damage_offset = pos;
  if (next == 0) {
    s.end = LogEnd::torn;
    s.problem = fmt::format(
        "log ends mid-record at byte {} after tick {} (torn tail: the writer was killed or the machine lost its "
        "last writes; {}); {} complete ticks kept, {} trailing bytes ignored",
        pos, last_good_tick, r.why, s.ticks, reader.size_ - pos);
    return;
  }
  s.end = LogEnd::corrupt;
  s.resumes_at = next;
  s.problem = fmt::format(
      "corrupt record at byte {} after tick {} (it should hold tick {} onwards): {}; valid records follow at byte "
      "{}, so this is damage in the middle of the log, not a torn tail; reading stops at tick {}",
      pos, last_good_tick, expected, r.why, next, last_good_tick);
}

std::string MatchLogReader::Scan::record(RecordType type, const std::uint8_t* p, std::uint32_t len, std::uint32_t framed) {
  if (seen_end) return fmt::format("a {} record follows the end record", to_string(type));
  switch (type) {
    case RecordType::header: return "a second header record";
    case RecordType::tick_block: return tick_block(p, len, framed);
    case RecordType::gap: return gap(p, len);
    case RecordType::keyframe: return keyframe(p, len, framed);
    case RecordType::index: return index(p, len);
    case RecordType::end: return end_record(p, len);
  }
  return fmt::format("unknown record type {}", static_cast<int>(type));  // check_record refuses these first
}

std::string MatchLogReader::Scan::tick_block(const std::uint8_t* p, std::uint32_t len, std::uint32_t framed) {
  if (len < 17) return "tick block shorter than its head";
  const std::uint64_t first = load_bytes<std::uint64_t>(p);
  const std::uint32_t count = load_bytes<std::uint32_t>(p + 8);
  if (count == 0) return "tick block with no ticks";
  if (first != expected)
    return fmt::format("tick block starts at tick {}, tick {} expected (no gap record explains the jump)", first, expected);
  s.blocks.push_back({first, count, pos, framed});
  try {
    reader.decode_block(s.blocks.size() - 1, raw);
    std::size_t at = 0;
    for (std::uint32_t k = 0; k < count; ++k) {
      decode_tick(raw, at, scratch, s.format_version);
      if (scratch.tick != first + k)
        throw LogError(fmt::format("entry {} holds tick {}, tick {} expected", k, scratch.tick, first + k));
    }
    if (at != raw.size()) throw LogError(fmt::format("{} bytes left over after {} ticks", raw.size() - at, count));
  } catch (const LogError& e) {
    s.blocks.pop_back();
    return fmt::format("tick block does not decode: {}", e.what());
  }
  if (s.first_tick == 0) s.first_tick = first;
  s.ticks += count;
  s.tick_block_bytes += framed;
  s.raw_tick_bytes += raw.size();
  expected = first + count;
  last_good_tick = expected - 1;
  s.last_tick = last_good_tick;
  return {};
}

std::string MatchLogReader::Scan::gap(const std::uint8_t* p, std::uint32_t len) {
  if (len != 17) return "gap record of the wrong size";
  const std::uint64_t first = load_bytes<std::uint64_t>(p), count = load_bytes<std::uint64_t>(p + 8);
  if (first != expected || count == 0)
    return fmt::format("gap record for ticks from {} while tick {} is expected", first, expected);
  s.gaps.push_back({first, count, pos});
  s.ticks_missing += count;
  expected += count;
  last_good_tick = expected - 1;
  return {};
}

std::string MatchLogReader::Scan::keyframe(const std::uint8_t* p, std::uint32_t len, std::uint32_t framed) {
  if (s.format_version < 2) return "a keyframe record in a format version 1 log";
  if (len < 13) return "keyframe record shorter than its head";
  const std::uint64_t tick = load_bytes<std::uint64_t>(p);
  const std::uint8_t codec = p[8];
  const std::uint32_t raw_size = load_bytes<std::uint32_t>(p + 9);
  if (tick == 0 || tick != last_good_tick || (!s.keyframes.empty() && tick <= s.keyframes.back().tick))
    return fmt::format("keyframe for tick {} after tick {} (a keyframe follows the block ending at its tick)", tick,
                       last_good_tick);
  if (codec > static_cast<std::uint8_t>(BlockCodec::zstd)) return fmt::format("unknown keyframe codec {}", codec);
  if (codec == static_cast<std::uint8_t>(BlockCodec::raw) && raw_size != len - 13)
    return "raw keyframe size disagrees with its head";
  s.keyframes.push_back({tick, pos, framed, raw_size});
  s.keyframe_bytes += framed;
  s.keyframe_raw_bytes += raw_size;
  return {};
}

std::string MatchLogReader::Scan::index(const std::uint8_t* p, std::uint32_t len) {
  const detail::IndexCounts counts = detail::index_counts(p, len, s.format_version);
  if (!counts.why.empty()) return counts.why;
  const bool final = p[8] != 0;
  const std::uint32_t n = counts.blocks, nk = counts.keyframes;
  for (std::uint32_t k = 0; k < nk; ++k) {
    const std::uint8_t* e = p + counts.keyframe_part + 16 * k;
    const std::uint64_t tick = load_bytes<std::uint64_t>(e), off = load_bytes<std::uint64_t>(e + 8);
    const auto it = std::lower_bound(s.keyframes.begin(), s.keyframes.end(), tick,
                                     [](const KeyframeInfo& x, std::uint64_t t) { return x.tick < t; });
    if (it == s.keyframes.end() || it->tick != tick || it->offset != off)
      return fmt::format("index keyframe entry {} (tick {} at byte {}) names no such keyframe", k, tick, off);
  }
  if (final && nk != s.keyframes.size()) return "the final index does not list every keyframe";
  // Every entry must name a block this scan saw at that offset with that tick range.
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint8_t* e = p + 13 + 20 * k;
    const std::uint64_t first = load_bytes<std::uint64_t>(e), off = load_bytes<std::uint64_t>(e + 12);
    const std::uint32_t cnt = load_bytes<std::uint32_t>(e + 8);
    const auto it = std::lower_bound(s.blocks.begin(), s.blocks.end(), first,
                                     [](const BlockInfo& b, std::uint64_t t) { return b.first_tick < t; });
    if (it == s.blocks.end() || it->first_tick != first || it->offset != off || it->tick_count != cnt)
      return fmt::format("index entry {} (ticks {}+{} at byte {}) names no such block", k, first, cnt, off);
  }
  if (final) {
    if (n != s.blocks.size()) return "the final index does not list every block";
    final_index_offset = pos;
  }
  ++s.index_records;
  return {};
}

std::string MatchLogReader::Scan::end_record(const std::uint8_t* p, std::uint32_t len) {
  if (len != 32) return "end record of the wrong size";
  if (load_bytes<std::uint64_t>(p) != final_index_offset || final_index_offset == 0) return "end record does not point at the final index";
  s.end_last_tick = load_bytes<std::uint64_t>(p + 8);
  s.end_ticks_written = load_bytes<std::uint64_t>(p + 16);
  s.end_ticks_dropped = load_bytes<std::uint64_t>(p + 24);
  if (s.end_last_tick != expected - 1)
    return fmt::format("end record says the last tick is {}, the log holds ticks up to {}", s.end_last_tick, expected - 1);
  seen_end = true;
  return {};
}

void MatchLogReader::Scan::finish() {
  if (seen_end) {
    s.end = LogEnd::closed;
    return;
  }
  s.end = LogEnd::unclosed;
  s.problem = fmt::format(
      "log ends at a record boundary after tick {} without an end record (the writer did not close it: killed "
      "between writes, or still writing); every tick in the file is intact",
      last_good_tick);
}

}  // namespace throng::matchlog
