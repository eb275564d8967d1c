#pragma once
// What the writer's parts share: timing helpers, durable write(2), record framing and the
// raw-or-zstd body of tick blocks and keyframes (FORMAT.md). Private to the match log library.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "throng/matchlog/format.h"

namespace throng::matchlog::detail {

using WriterClock = std::chrono::steady_clock;

inline std::uint64_t ns_between(WriterClock::time_point a, WriterClock::time_point b) {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(b - a).count());
}

inline void atomic_max(std::atomic<std::uint64_t>& a, std::uint64_t v) {
  std::uint64_t cur = a.load(std::memory_order_relaxed);
  while (v > cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}

// write(2) until everything is written; "" or the error.
std::string write_all(int fd, const std::uint8_t* p, std::size_t n);

// pread(2) of exactly n bytes at `offset`; "" or the error (a short file is one).
std::string read_all_at(int fd, std::uint8_t* p, std::size_t n, std::uint64_t offset);

// Appends one framed record (length, type, payload, CRC-32C over all of it) to `out`.
void frame_record(RecordType type, const std::vector<std::uint8_t>& payload, std::vector<std::uint8_t>& out);

// Appends codec u8, raw_size u32 and the body to `payload`: one zstd frame of `raw` when `zctx` (a
// ZSTD_CCtx, null = stored raw) makes it smaller, else `raw` itself. `scratch` is reused.
void append_body(void* zctx, int zstd_level, const std::vector<std::uint8_t>& raw, std::vector<std::uint8_t>& scratch,
                 std::vector<std::uint8_t>& payload);

}  // namespace throng::matchlog::detail
