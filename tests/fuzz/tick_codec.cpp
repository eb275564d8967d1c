// The match log's tick entries (decode_tick: joins, commands, parameter changes, flags, hash) as
// the reader decodes them from a tick block. Input: one byte choosing the format version (1..3),
// then tick entries back to back. Bad input throws LogError.
#include <cstdint>
#include <cstdlib>
#include <span>

#include "throng/matchlog/format.h"
#include "throng/matchlog/tick_record.h"

using namespace throng;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::uint32_t version = matchlog::kOldestReadableFormatVersion + data[0] % matchlog::kFormatVersion;
  const std::span<const std::uint8_t> bytes(data + 1, size - 1);
  std::size_t pos = 0;
  matchlog::TickRecord t;
  try {
    while (pos < bytes.size()) {
      const std::size_t before = pos;
      matchlog::decode_tick(bytes, pos, t, version);
      if (pos <= before || pos > bytes.size()) std::abort();  // must advance, within the bytes
    }
  } catch (const matchlog::LogError&) {
  }
  return 0;
}
