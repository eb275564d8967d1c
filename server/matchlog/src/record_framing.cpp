// Record framing checks (record_framing.h).
#include "record_framing.h"

#include <fmt/format.h>

#include "throng/core/byte_io.h"
#include "throng/matchlog/crc32c.h"
#include "throng/matchlog/format.h"

namespace throng::matchlog::detail {

IndexCounts index_counts(const std::uint8_t* payload, std::uint32_t length, std::uint32_t format_version) {
  IndexCounts c;
  if (length < 13) {
    c.why = "index record shorter than its head";
    return c;
  }
  c.blocks = load_bytes<std::uint32_t>(payload + 9);
  const std::uint64_t block_part = 13 + static_cast<std::uint64_t>(c.blocks) * 20;
  if (format_version >= 2) {
    if (length < block_part + 4) {
      c.why = "index record length disagrees with its count";
      return c;
    }
    c.keyframes = load_bytes<std::uint32_t>(payload + block_part);
    c.keyframe_part = block_part + 4;
    if (c.keyframe_part + static_cast<std::uint64_t>(c.keyframes) * 16 != length)
      c.why = "index record length disagrees with its counts";
  } else if (block_part != length) {
    c.why = "index record length disagrees with its count";
  }
  return c;
}

RecordCheck check_record(const std::uint8_t* data, std::size_t size, std::size_t pos) {
  RecordCheck r;
  if (size - pos < kRecordOverheadBytes) {
    r.why = fmt::format("only {} bytes left, a record needs at least {}", size - pos, kRecordOverheadBytes);
    return r;
  }
  r.length = load_bytes<std::uint32_t>(data + pos);
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
  const std::uint32_t stored = load_bytes<std::uint32_t>(data + pos + 5 + r.length);
  const std::uint32_t actual = crc32c(data + pos, 5 + r.length);
  if (stored != actual) {
    r.why = fmt::format("CRC mismatch in a {} record (stored {:08x}, computed {:08x})",
                        to_string(static_cast<RecordType>(r.type)), stored, actual);
    return r;
  }
  r.ok = true;
  return r;
}

std::size_t find_valid_record_after(const std::uint8_t* data, std::size_t size, std::size_t from, std::uint64_t last_tick) {
  for (std::size_t q = from + 1; q + kRecordOverheadBytes <= size; ++q) {
    const std::uint8_t type = data[q + 4];
    if (!is_known_record_type(type) || type == static_cast<std::uint8_t>(RecordType::header)) continue;
    const std::uint32_t len = load_bytes<std::uint32_t>(data + q);
    if (len > kMaxRecordPayload || size - q - kRecordOverheadBytes < len) continue;
    const std::uint8_t* p = data + q + 5;
    switch (static_cast<RecordType>(type)) {
      case RecordType::tick_block:
      case RecordType::gap: {
        if (len < 16) continue;
        const std::uint64_t first = load_bytes<std::uint64_t>(p);
        if (first <= last_tick || first - last_tick > (1ull << 32)) continue;
        break;
      }
      case RecordType::index:
        if (len < 13 || load_bytes<std::uint64_t>(p) >= q) continue;
        break;
      case RecordType::end:
        if (len != 32 || load_bytes<std::uint64_t>(p) >= q) continue;
        break;
      case RecordType::keyframe: {
        if (len < 13) continue;
        const std::uint64_t tick = load_bytes<std::uint64_t>(p);
        if (tick == 0 || tick > last_tick + (1ull << 32)) continue;
        break;
      }
      default: continue;
    }
    if (check_record(data, size, q).ok) return q;
  }
  return 0;
}

}  // namespace throng::matchlog::detail
