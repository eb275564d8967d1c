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

#include "throng/core/byte_io.h"
#include "record_framing.h"
#include "throng/matchlog/crc32c.h"
#include "throng/scene/scene_json.h"

namespace throng::matchlog {
namespace {

using detail::check_record;
using detail::RecordCheck;

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
  const std::uint32_t version = load_bytes<std::uint32_t>(data_ + 8);
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
  const std::uint32_t len = load_bytes<std::uint32_t>(data_ + b.offset);
  if (len < 17) throw LogError("tick block payload shorter than its 17-byte head");
  const std::uint8_t codec = p[12];
  const std::uint32_t raw_size = load_bytes<std::uint32_t>(p + 13);
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
  const std::uint32_t len = load_bytes<std::uint32_t>(data_ + k.offset);
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

std::uint64_t start_keyframe_tick(const LogScan& s) {
  if (s.gaps.empty() || s.keyframes.empty() || s.gaps.front().first_tick != 1) return 0;
  const std::uint64_t t = s.gaps.front().count;
  return s.keyframes.front().tick == t ? t : 0;
}

std::span<const GapInfo> holes(const LogScan& s) {
  return std::span<const GapInfo>(s.gaps).subspan(start_keyframe_tick(s) > 0 ? 1 : 0);
}

}  // namespace throng::matchlog
