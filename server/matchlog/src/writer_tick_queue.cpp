// The tick queue: append_tick on the tick thread (ring slot or spill list, never waiting for
// I/O), and the writer thread taking ticks off it into blocks (process_one, consume).
#include "throng/matchlog/writer.h"

#include <stdexcept>

#include <fmt/format.h>

#include "throng/core/byte_io.h"
#include "throng/matchlog/tick_record.h"
#include "writer_io.h"

namespace throng::matchlog {

using Clock = detail::WriterClock;

void MatchLogWriter::append_tick(std::uint64_t tick, const match::TickInputs& inputs, std::uint64_t state_hash,
                                 std::uint8_t flags) {
  const Clock::time_point t0 = Clock::now();
  if (!began_ || closed_) throw std::logic_error("MatchLogWriter::append_tick before begin() or after close()");
  if (tick != next_tick_)
    throw std::invalid_argument(fmt::format("MatchLogWriter::append_tick: tick {} given, {} expected (ticks are consecutive from 1)",
                                            tick, next_tick_));
  if ((flags & ~kKnownTickFlags) != 0) throw std::invalid_argument("MatchLogWriter::append_tick: unknown flag bits");
  ++next_tick_;
  // release: a keyframe appended for the previous tick is visible to a writer that sees this count
  // (the writer waits for that to decide whether the previous tick has a keyframe).
  appended_.fetch_add(1, std::memory_order_release);
  last_tick_dropped_ = false;

  if (io_failed_.load(std::memory_order_relaxed)) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    last_tick_dropped_ = true;
  } else {
    const std::uint64_t h = head_.load(std::memory_order_relaxed);
    const std::uint64_t t = tail_.load(std::memory_order_acquire);
    if (spill_count_.load(std::memory_order_acquire) == 0 && h - t < ring_.size()) {
      std::vector<std::uint8_t>& b = ring_[h % ring_.size()].bytes;
      b.clear();
      encode_tick(tick, inputs, state_hash, flags, b);
      head_.store(h + 1, std::memory_order_release);
    } else {
      // The disk is behind: keep the tick in the spill list (allocates, but never waits for I/O),
      // up to the hard cap; beyond it the tick is dropped, counted, and marked by a gap record.
      const std::size_t size = encoded_tick_size(inputs);
      if (spill_bytes_.load(std::memory_order_relaxed) + size > opt_.spill_cap_bytes) {
        dropped_.fetch_add(1, std::memory_order_relaxed);
        last_tick_dropped_ = true;
      } else {
        std::vector<std::uint8_t> v;
        v.reserve(size);
        encode_tick(tick, inputs, state_hash, flags, v);
        {
          std::lock_guard<std::mutex> lock(spill_mutex_);
          spill_.push_back(std::move(v));
        }
        spill_bytes_.fetch_add(size, std::memory_order_relaxed);
        spill_count_.fetch_add(1, std::memory_order_release);
        spilled_.fetch_add(1, std::memory_order_relaxed);
      }
    }
  }
  const std::uint64_t backlog = appended_.load(std::memory_order_relaxed) - written_.load(std::memory_order_relaxed) -
                                dropped_.load(std::memory_order_relaxed);
  detail::atomic_max(backlog_high_, backlog);
  // No notify here: waking the writer thread from the tick thread lets the scheduler run the
  // writer (zstd of a whole block) on this core right away and preempt the tick, which showed in
  // the append's p99 (docs/design/match-log.md). The writer polls every poll_ms instead.

  const std::uint64_t ns = detail::ns_between(t0, Clock::now());
  detail::atomic_max(max_append_ns_, ns);
  const std::size_t bin = static_cast<std::size_t>(ns / 100);
  if (bin < kHistBins) hist_[bin].fetch_add(1, std::memory_order_relaxed);
  else hist_over_.fetch_add(1, std::memory_order_relaxed);
}

bool MatchLogWriter::process_one() {
  if (kf_pending_ != 0 && !resolve_keyframe()) return false;
  const std::uint64_t t = tail_.load(std::memory_order_relaxed);
  if (t < head_.load(std::memory_order_acquire)) {
    consume(ring_[t % ring_.size()].bytes);
    tail_.store(t + 1, std::memory_order_release);
    return true;
  }
  std::vector<std::uint8_t> v;
  {
    std::lock_guard<std::mutex> lock(spill_mutex_);
    if (spill_.empty()) return false;
    v = std::move(spill_.front());
    spill_.pop_front();
  }
  consume(v);
  spill_bytes_.fetch_sub(v.size(), std::memory_order_relaxed);
  spill_count_.fetch_sub(1, std::memory_order_release);
  return true;
}

void MatchLogWriter::consume(const std::vector<std::uint8_t>& entry) {
  if (io_failed_.load(std::memory_order_relaxed)) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  const std::uint64_t tick = load_bytes<std::uint64_t>(entry.data());
  if (tick != expected_tick_) {  // the tick thread dropped expected_tick_..tick-1 (spill cap)
    flush_block();
    write_gap(expected_tick_, tick - expected_tick_);
    expected_tick_ = tick;
  }
  const std::uint64_t window = (tick - 1) / opt_.block_ticks;
  if (block_count_ > 0 && window != block_window_) flush_block();
  if (block_count_ == 0) {
    block_first_ = tick;
    block_window_ = window;
  }
  block_raw_.insert(block_raw_.end(), entry.begin(), entry.end());
  ++block_count_;
  ++expected_tick_;
  if (tick % opt_.block_ticks == 0) {
    flush_block();
    if (opt_.keyframe_interval_ticks > 0 && tick % opt_.keyframe_interval_ticks == 0) {
      kf_pending_ = tick;  // the keyframe (if any) and the index follow once the tick thread is past it
      resolve_keyframe();
      return;
    }
    if (opt_.index_interval_ticks > 0 && tick % opt_.index_interval_ticks == 0) write_index(false);
  }
}

}  // namespace throng::matchlog
