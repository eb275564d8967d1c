// MatchLogReader: header checks, the validating scan with torn-tail / corruption classification,
// and block decoding for sequential reads and seeks.
#include "throng/matchlog/reader.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>
#include <xxhash.h>
#include <zstd.h>

#include "byte_io.h"
#include "throng/matchlog/crc32c.h"
#include "throng/scene/scene_json.h"

namespace throng::matchlog {
namespace {

using detail::load_u32;
using detail::load_u64;

struct RecordCheck {
  bool ok = false;
  std::uint8_t type = 0;
  std::uint32_t length = 0;
  std::string why;  // when !ok
};

RecordCheck check_record(const std::uint8_t* data, std::size_t size, std::size_t pos) {
  RecordCheck r;
  if (size - pos < kRecordOverheadBytes) {
    r.why = fmt::format("only {} bytes left, a record needs at least {}", size - pos, kRecordOverheadBytes);
    return r;
  }
  r.length = load_u32(data + pos);
  r.type = data[pos + 4];
  if (!is_known_record_type(r.type)) {
    r.why = fmt::format("unknown record type {}", r.type);
    return r;
  }
  if (r.length > kMaxRecordPayload) {
    r.why = fmt::format("implausible record length {}", r.length);
    return r;
  }
  if (size - pos - kRecordOverheadBytes < r.length) {
    r.why = fmt::format("the {} record needs {} bytes, only {} are left", to_string(static_cast<RecordType>(r.type)),
                        r.length + kRecordOverheadBytes, size - pos);
    return r;
  }
  const std::uint32_t stored = load_u32(data + pos + 5 + r.length);
  const std::uint32_t actual = crc32c(data + pos, 5 + r.length);
  if (stored != actual) {
    r.why = fmt::format("CRC mismatch in a {} record (stored {:08x}, computed {:08x})",
                        to_string(static_cast<RecordType>(r.type)), stored, actual);
    return r;
  }
  r.ok = true;
  return r;
}

// After damage at `from`: is there a valid record further on? Cheap field checks before the CRC
// keep this linear on garbage (a tick block must continue after last_tick, an index/end record
// can only point backwards).
std::size_t find_valid_record_after(const std::uint8_t* data, std::size_t size, std::size_t from, std::uint64_t last_tick) {
  for (std::size_t q = from + 1; q + kRecordOverheadBytes <= size; ++q) {
    const std::uint8_t type = data[q + 4];
    if (!is_known_record_type(type) || type == static_cast<std::uint8_t>(RecordType::header)) continue;
    const std::uint32_t len = load_u32(data + q);
    if (len > kMaxRecordPayload || size - q - kRecordOverheadBytes < len) continue;
    const std::uint8_t* p = data + q + 5;
    switch (static_cast<RecordType>(type)) {
      case RecordType::tick_block:
      case RecordType::gap: {
        if (len < 16) continue;
        const std::uint64_t first = load_u64(p);
        if (first <= last_tick || first - last_tick > (1ull << 32)) continue;
        break;
      }
      case RecordType::index:
        if (len < 13 || load_u64(p) >= q) continue;
        break;
      case RecordType::end:
        if (len != 32 || load_u64(p) >= q) continue;
        break;
      case RecordType::keyframe: {
        if (len < 13) continue;
        const std::uint64_t tick = load_u64(p);
        if (tick == 0 || tick > last_tick + (1ull << 32)) continue;
        break;
      }
      default: continue;
    }
    if (check_record(data, size, q).ok) return q;
  }
  return 0;
}

}  // namespace

const char* to_string(LogEnd e) {
  switch (e) {
    case LogEnd::closed: return "closed";
    case LogEnd::unclosed: return "unclosed";
    case LogEnd::torn: return "torn";
    case LogEnd::corrupt: return "corrupt";
  }
  return "?";
}

MatchLogReader::MatchLogReader(const std::string& path) : path_(path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw LogError(fmt::format("{}: cannot open: {}", path, std::strerror(errno)));
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int e = errno;
    ::close(fd);
    throw LogError(fmt::format("{}: cannot stat: {}", path, std::strerror(e)));
  }
  size_ = static_cast<std::size_t>(st.st_size);
  if (size_ > 0) {
    map_ = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (map_ == MAP_FAILED) {
      const int e = errno;
      map_ = nullptr;
      ::close(fd);
      throw LogError(fmt::format("{}: cannot map: {}", path, std::strerror(e)));
    }
    data_ = static_cast<const std::uint8_t*>(map_);
  }
  ::close(fd);
  try {
    read_header();
    scan_records();
  } catch (...) {
    if (map_ != nullptr) ::munmap(map_, size_);
    map_ = nullptr;
    throw;
  }
}

MatchLogReader::~MatchLogReader() {
  if (map_ != nullptr) ::munmap(map_, size_);
}

void MatchLogReader::read_header() {
  scan_.file_bytes = size_;
  if (size_ == 0) throw LogError(fmt::format("{}: empty file, not a Throng match log", path_));
  const std::size_t m = std::min<std::size_t>(size_, 8);
  if (std::memcmp(data_, kMagic, m) != 0)
    throw LogError(fmt::format("{}: not a Throng match log (the file does not start with the \\x89THRONG\\n magic)", path_));
  if (size_ < kFilePreambleBytes)
    throw LogError(fmt::format("{}: truncated header: the file is only {} bytes (the preamble alone is {})", path_, size_,
                               kFilePreambleBytes));
  const std::uint32_t version = load_u32(data_ + 8);
  if (version < kOldestReadableFormatVersion || version > kFormatVersion)
    throw LogError(fmt::format("{}: match log format version {} is not supported (this build reads format versions {}..{})",
                               path_, version, kOldestReadableFormatVersion, kFormatVersion));
  scan_.format_version = version;
  const RecordCheck r = check_record(data_, size_, kFilePreambleBytes);
  if (!r.ok) {
    if (size_ - kFilePreambleBytes < kRecordOverheadBytes ||
        (r.type == static_cast<std::uint8_t>(RecordType::header) && r.length <= kMaxRecordPayload &&
         size_ - kFilePreambleBytes - kRecordOverheadBytes < r.length))
      throw LogError(fmt::format("{}: truncated header: {} (file is {} bytes)", path_, r.why, size_));
    throw LogError(fmt::format("{}: corrupt header record at byte {}: {}", path_, kFilePreambleBytes, r.why));
  }
  if (r.type != static_cast<std::uint8_t>(RecordType::header))
    throw LogError(fmt::format("{}: corrupt log: the first record is a {} record, not the header", path_,
                               to_string(static_cast<RecordType>(r.type))));
  const std::string text(reinterpret_cast<const char*>(data_ + kFilePreambleBytes + 5), r.length);
  try {
    header_ = header_from_json_text(text);
  } catch (const LogError& e) {
    throw LogError(fmt::format("{}: {}", path_, e.what()));
  }
  if (header_.format_version != version)
    throw LogError(fmt::format("{}: corrupt header: format version {} in the preamble, {} in the header", path_, version,
                               header_.format_version));
  const std::string scene_text = scene::scene_to_json(header_.scene).dump();
  scan_.scene_hash_matches = XXH3_64bits(scene_text.data(), scene_text.size()) == header_.scene_hash;
  scan_.header_bytes = kFilePreambleBytes + kRecordOverheadBytes + r.length;
}

void MatchLogReader::decode_block(std::size_t index, std::vector<std::uint8_t>& raw) const {
  const BlockInfo& b = scan_.blocks[index];
  const std::uint8_t* p = data_ + b.offset + 5;
  const std::uint32_t len = load_u32(data_ + b.offset);
  if (len < 17) throw LogError("tick block payload shorter than its 17-byte head");
  const std::uint8_t codec = p[12];
  const std::uint32_t raw_size = load_u32(p + 13);
  const std::uint8_t* body = p + 17;
  const std::size_t body_size = len - 17;
  if (codec == static_cast<std::uint8_t>(BlockCodec::raw)) {
    if (body_size != raw_size) throw LogError(fmt::format("raw tick block holds {} bytes, its head says {}", body_size, raw_size));
    raw.assign(body, body + body_size);
  } else if (codec == static_cast<std::uint8_t>(BlockCodec::zstd)) {
    if (raw_size > kMaxRecordPayload) throw LogError(fmt::format("implausible uncompressed size {}", raw_size));
    raw.resize(raw_size);
    const std::size_t n = ZSTD_decompress(raw.data(), raw.size(), body, body_size);
    if (ZSTD_isError(n)) throw LogError(std::string("zstd: ") + ZSTD_getErrorName(n));
    if (n != raw_size) throw LogError(fmt::format("zstd block inflated to {} bytes, its head says {}", n, raw_size));
  } else {
    throw LogError(fmt::format("unknown block codec {}", codec));
  }
}

void MatchLogReader::scan_records() {
  LogScan& s = scan_;
  std::size_t pos = s.header_bytes;
  std::uint64_t expected = 1;  // next tick the file should hold
  std::uint64_t last_good_tick = 0;
  bool seen_end = false;
  std::uint64_t final_index_offset = 0;
  std::vector<std::uint8_t> raw;
  TickRecord scratch;
  std::string damage;  // non-empty: stop at pos

  auto semantic = [&](const std::string& why) { damage = why; };

  while (pos < size_) {
    const RecordCheck r = check_record(data_, size_, pos);
    if (!r.ok) {
      damage = r.why;
      const std::size_t next = find_valid_record_after(data_, size_, pos, last_good_tick);
      if (next == 0) {
        s.end = LogEnd::torn;
        s.damage_offset = pos;
        s.problem = fmt::format(
            "log ends mid-record at byte {} after tick {} (torn tail: the writer was killed or the machine lost its "
            "last writes; {}); {} complete ticks kept, {} trailing bytes ignored",
            pos, last_good_tick, r.why, s.ticks, size_ - pos);
        break;
      }
      s.end = LogEnd::corrupt;
      s.damage_offset = pos;
      s.resumes_at = next;
      s.problem = fmt::format(
          "corrupt record at byte {} after tick {} (it should hold tick {} onwards): {}; valid records follow at byte "
          "{}, so this is damage in the middle of the log, not a torn tail; reading stops at tick {}",
          pos, last_good_tick, expected, r.why, next, last_good_tick);
      return;
    }
    const std::uint8_t* p = data_ + pos + 5;
    const std::uint32_t len = r.length;
    const std::uint32_t framed = len + static_cast<std::uint32_t>(kRecordOverheadBytes);
    const auto type = static_cast<RecordType>(r.type);
    if (seen_end) {
      semantic(fmt::format("a {} record follows the end record", to_string(type)));
    } else {
      switch (type) {
        case RecordType::header: semantic("a second header record"); break;
        case RecordType::tick_block: {
          if (len < 17) { semantic("tick block shorter than its head"); break; }
          const std::uint64_t first = load_u64(p);
          const std::uint32_t count = load_u32(p + 8);
          if (count == 0) { semantic("tick block with no ticks"); break; }
          if (first != expected) {
            semantic(fmt::format("tick block starts at tick {}, tick {} expected (no gap record explains the jump)", first, expected));
            break;
          }
          s.blocks.push_back({first, count, pos, framed});
          try {
            decode_block(s.blocks.size() - 1, raw);
            std::size_t at = 0;
            for (std::uint32_t k = 0; k < count; ++k) {
              decode_tick(raw, at, scratch, s.format_version);
              if (scratch.tick != first + k)
                throw LogError(fmt::format("entry {} holds tick {}, tick {} expected", k, scratch.tick, first + k));
            }
            if (at != raw.size()) throw LogError(fmt::format("{} bytes left over after {} ticks", raw.size() - at, count));
          } catch (const LogError& e) {
            s.blocks.pop_back();
            semantic(fmt::format("tick block does not decode: {}", e.what()));
            break;
          }
          if (s.first_tick == 0) s.first_tick = first;
          s.ticks += count;
          s.tick_block_bytes += framed;
          s.raw_tick_bytes += raw.size();
          expected = first + count;
          last_good_tick = expected - 1;
          s.last_tick = last_good_tick;
          break;
        }
        case RecordType::gap: {
          if (len != 17) { semantic("gap record of the wrong size"); break; }
          const std::uint64_t first = load_u64(p), count = load_u64(p + 8);
          if (first != expected || count == 0) {
            semantic(fmt::format("gap record for ticks from {} while tick {} is expected", first, expected));
            break;
          }
          s.gaps.push_back({first, count, pos});
          s.ticks_missing += count;
          expected += count;
          last_good_tick = expected - 1;
          break;
        }
        case RecordType::keyframe: {
          if (s.format_version < 2) { semantic("a keyframe record in a format version 1 log"); break; }
          if (len < 13) { semantic("keyframe record shorter than its head"); break; }
          const std::uint64_t tick = load_u64(p);
          const std::uint8_t codec = p[8];
          const std::uint32_t raw_size = load_u32(p + 9);
          if (tick == 0 || tick != last_good_tick || (!s.keyframes.empty() && tick <= s.keyframes.back().tick)) {
            semantic(fmt::format("keyframe for tick {} after tick {} (a keyframe follows the block ending at its tick)",
                                 tick, last_good_tick));
            break;
          }
          if (codec > static_cast<std::uint8_t>(BlockCodec::zstd)) { semantic(fmt::format("unknown keyframe codec {}", codec)); break; }
          if (codec == static_cast<std::uint8_t>(BlockCodec::raw) && raw_size != len - 13) {
            semantic("raw keyframe size disagrees with its head");
            break;
          }
          s.keyframes.push_back({tick, pos, framed, raw_size});
          s.keyframe_bytes += framed;
          s.keyframe_raw_bytes += raw_size;
          break;
        }
        case RecordType::index: {
          if (len < 13) { semantic("index record shorter than its head"); break; }
          const bool final = p[8] != 0;
          const std::uint32_t n = load_u32(p + 9);
          const std::uint64_t block_part = 13 + static_cast<std::uint64_t>(n) * 20;
          std::uint32_t nk = 0;
          if (s.format_version >= 2) {
            if (len < block_part + 4) { semantic("index record length disagrees with its count"); break; }
            nk = load_u32(p + block_part);
            if (block_part + 4 + static_cast<std::uint64_t>(nk) * 16 != len) { semantic("index record length disagrees with its counts"); break; }
          } else if (block_part != len) {
            semantic("index record length disagrees with its count");
            break;
          }
          for (std::uint32_t k = 0; k < nk && damage.empty(); ++k) {
            const std::uint8_t* e = p + block_part + 4 + 16 * k;
            const std::uint64_t tick = load_u64(e), off = load_u64(e + 8);
            const auto it = std::lower_bound(s.keyframes.begin(), s.keyframes.end(), tick,
                                             [](const KeyframeInfo& x, std::uint64_t t) { return x.tick < t; });
            if (it == s.keyframes.end() || it->tick != tick || it->offset != off)
              semantic(fmt::format("index keyframe entry {} (tick {} at byte {}) names no such keyframe", k, tick, off));
          }
          if (final && nk != s.keyframes.size() && damage.empty()) semantic("the final index does not list every keyframe");
          // Every entry must name a block this scan saw at that offset with that tick range.
          for (std::uint32_t k = 0; k < n && damage.empty(); ++k) {
            const std::uint8_t* e = p + 13 + 20 * k;
            const std::uint64_t first = load_u64(e), off = load_u64(e + 12);
            const std::uint32_t cnt = load_u32(e + 8);
            const auto it = std::lower_bound(s.blocks.begin(), s.blocks.end(), first,
                                             [](const BlockInfo& b, std::uint64_t t) { return b.first_tick < t; });
            if (it == s.blocks.end() || it->first_tick != first || it->offset != off || it->tick_count != cnt)
              semantic(fmt::format("index entry {} (ticks {}+{} at byte {}) names no such block", k, first, cnt, off));
          }
          if (final) {
            if (n != s.blocks.size()) semantic("the final index does not list every block");
            final_index_offset = pos;
          }
          ++s.index_records;
          break;
        }
        case RecordType::end: {
          if (len != 32) { semantic("end record of the wrong size"); break; }
          if (load_u64(p) != final_index_offset || final_index_offset == 0) {
            semantic("end record does not point at the final index");
            break;
          }
          s.end_last_tick = load_u64(p + 8);
          s.end_ticks_written = load_u64(p + 16);
          s.end_ticks_dropped = load_u64(p + 24);
          if (s.end_last_tick != expected - 1) {
            semantic(fmt::format("end record says the last tick is {}, the log holds ticks up to {}", s.end_last_tick, expected - 1));
            break;
          }
          seen_end = true;
          break;
        }
      }
    }
    if (!damage.empty()) {
      s.end = LogEnd::corrupt;
      s.damage_offset = pos;
      s.problem = fmt::format("corrupt {} record at byte {} after tick {}: {}; reading stops at tick {}", to_string(type),
                              pos, last_good_tick, damage, last_good_tick);
      return;
    }
    pos += framed;
  }
  if (s.end == LogEnd::torn) return;
  if (seen_end) {
    s.end = LogEnd::closed;
  } else {
    s.end = LogEnd::unclosed;
    s.problem = fmt::format(
        "log ends at a record boundary after tick {} without an end record (the writer did not close it: killed "
        "between writes, or still writing); every tick in the file is intact",
        last_good_tick);
  }
}

const BlockInfo* MatchLogReader::find_block(std::uint64_t tick) const {
  const auto& b = scan_.blocks;
  auto it = std::upper_bound(b.begin(), b.end(), tick, [](std::uint64_t t, const BlockInfo& x) { return t < x.first_tick; });
  if (it == b.begin()) return nullptr;
  --it;
  return tick < it->first_tick + it->tick_count ? &*it : nullptr;
}

const KeyframeInfo* MatchLogReader::find_keyframe(std::uint64_t tick) const {
  const auto& k = scan_.keyframes;
  auto it = std::upper_bound(k.begin(), k.end(), tick, [](std::uint64_t t, const KeyframeInfo& x) { return t < x.tick; });
  if (it == k.begin()) return nullptr;
  return &*(it - 1);
}

void MatchLogReader::read_keyframe(const KeyframeInfo& k, std::vector<std::uint8_t>& out) const {
  const std::uint8_t* p = data_ + k.offset + 5;
  const std::uint32_t len = load_u32(data_ + k.offset);
  const std::uint8_t codec = p[8];
  const std::uint8_t* body = p + 13;
  const std::size_t body_size = len - 13;
  if (codec == static_cast<std::uint8_t>(BlockCodec::raw)) {
    out.assign(body, body + body_size);
    return;
  }
  if (k.raw_size > (1u << 30))
    throw LogError(fmt::format("{}: keyframe at byte {}: implausible size {}", path_, k.offset, k.raw_size));
  out.resize(k.raw_size);
  const std::size_t n = ZSTD_decompress(out.data(), out.size(), body, body_size);
  if (ZSTD_isError(n) || n != k.raw_size)
    throw LogError(fmt::format("{}: keyframe for tick {} at byte {} does not inflate to its {} bytes{}", path_, k.tick,
                               k.offset, k.raw_size, ZSTD_isError(n) ? std::string(": ") + ZSTD_getErrorName(n) : ""));
}

bool TickCursor::seek(std::uint64_t tick) {
  const auto& b = r_.scan().blocks;
  auto it = std::lower_bound(b.begin(), b.end(), tick,
                             [](const BlockInfo& x, std::uint64_t t) { return x.first_tick + x.tick_count <= t; });
  loaded_ = false;
  pos_ = 0;
  block_ = static_cast<std::size_t>(it - b.begin());
  if (it == b.end()) return false;
  r_.decode_block(block_, raw_);
  loaded_ = true;
  TickRecord skip;
  for (std::uint64_t t = it->first_tick; t < tick; ++t) decode_tick(raw_, pos_, skip, r_.scan().format_version);
  return true;
}

bool TickCursor::next(TickRecord& out) {
  for (;;) {
    if (block_ >= r_.scan().blocks.size()) return false;
    if (!loaded_) {
      r_.decode_block(block_, raw_);
      pos_ = 0;
      loaded_ = true;
    }
    if (pos_ < raw_.size()) {
      decode_tick(raw_, pos_, out, r_.scan().format_version);
      return true;
    }
    ++block_;
    loaded_ = false;
  }
}

void MatchLogReader::rewind() {
  block_ = 0;
  raw_pos_ = 0;
  raw_loaded_ = false;
}

bool MatchLogReader::next(TickRecord& out) {
  for (;;) {
    if (block_ >= scan_.blocks.size()) return false;
    if (!raw_loaded_) {
      decode_block(block_, raw_);
      raw_pos_ = 0;
      raw_loaded_ = true;
    }
    if (raw_pos_ < raw_.size()) {
      decode_tick(raw_, raw_pos_, out, scan_.format_version);
      return true;
    }
    ++block_;
    raw_loaded_ = false;
  }
}

bool MatchLogReader::seek(std::uint64_t tick) {
  const auto& b = scan_.blocks;
  // First block whose last tick is >= tick.
  auto it = std::lower_bound(b.begin(), b.end(), tick,
                             [](const BlockInfo& x, std::uint64_t t) { return x.first_tick + x.tick_count <= t; });
  rewind();
  if (it == b.end()) {
    block_ = b.size();
    return false;
  }
  block_ = static_cast<std::size_t>(it - b.begin());
  decode_block(block_, raw_);
  raw_pos_ = 0;
  raw_loaded_ = true;
  TickRecord skip;
  for (std::uint64_t t = it->first_tick; t < tick; ++t) decode_tick(raw_, raw_pos_, skip, scan_.format_version);
  return true;
}

}  // namespace throng::matchlog
