#pragma once
// One tick as the log stores it, and its binary encoding (little-endian, explicit field sizes,
// never a memcpy of a struct; layout in FORMAT.md "Tick entry").
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "throng/match/input_queue.h"

namespace throng::matchlog {

struct TickRecord {
  std::uint64_t tick = 0;        // Match tick number (the first tick is 1)
  std::uint64_t state_hash = 0;  // Match::state_hash() after the tick
  std::uint8_t flags = 0;        // kTick* flags (format.h)
  match::TickInputs inputs;      // Match::last_inputs() of the tick, in applied order
};

// Appends one tick entry to out (out is not cleared). Does not allocate when out has capacity.
void encode_tick(std::uint64_t tick, const match::TickInputs& inputs, std::uint64_t state_hash, std::uint8_t flags,
                 std::vector<std::uint8_t>& out);
// Bytes encode_tick will append.
std::size_t encoded_tick_size(const match::TickInputs& inputs);

// Decodes the entry starting at bytes[pos]; advances pos past it. Throws LogError (message without
// file offset: the caller adds it) when the entry is malformed or runs past the end.
// format_version is the log's: entries before version 3 carry no senders (they decode as zeros,
// as the match saw them then).
void decode_tick(std::span<const std::uint8_t> bytes, std::size_t& pos, TickRecord& out, std::uint32_t format_version);

}  // namespace throng::matchlog
