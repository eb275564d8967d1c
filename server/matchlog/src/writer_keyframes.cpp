// World keyframes: slots the tick thread fills (copied or swapped, dropped when the writer is
// behind), and their placement right after the block ending at their tick (resolve_keyframe).
#include "throng/matchlog/writer.h"

#include <stdexcept>

#include <fmt/format.h>

#include "throng/core/byte_io.h"
#include "writer_io.h"

namespace throng::matchlog {

using Clock = detail::WriterClock;

MatchLogWriter::KeyframeSlot* MatchLogWriter::keyframe_slot(std::uint64_t tick) {
  if (!began_ || closed_) throw std::logic_error("MatchLogWriter::append_keyframe before begin() or after close()");
  if (opt_.keyframe_interval_ticks == 0)
    throw std::invalid_argument("MatchLogWriter::append_keyframe: keyframes are off (keyframe_interval_ticks = 0)");
  if (tick + 1 != next_tick_ || tick % opt_.keyframe_interval_ticks != 0)
    throw std::invalid_argument(fmt::format(
        "MatchLogWriter::append_keyframe: tick {} given; a keyframe belongs to the last appended tick ({}) and that "
        "tick must be a multiple of the keyframe interval ({})",
        tick, next_tick_ - 1, opt_.keyframe_interval_ticks));
  kf_appended_.fetch_add(1, std::memory_order_relaxed);
  const std::uint64_t h = kf_head_.load(std::memory_order_relaxed);
  const std::uint64_t t = kf_tail_.load(std::memory_order_acquire);
  if (last_tick_dropped_ || io_failed_.load(std::memory_order_relaxed) || h - t >= kf_ring_.size()) {
    kf_dropped_.fetch_add(1, std::memory_order_relaxed);
    return nullptr;
  }
  KeyframeSlot& s = kf_ring_[h % kf_ring_.size()];
  s.tick = tick;
  return &s;
}

void MatchLogWriter::publish_keyframe(Clock::time_point t0) {
  kf_head_.store(kf_head_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
  detail::atomic_max(max_kf_append_ns_, detail::ns_between(t0, Clock::now()));
}

void MatchLogWriter::append_keyframe(std::uint64_t tick, std::span<const std::uint8_t> checkpoint) {
  const Clock::time_point t0 = Clock::now();
  KeyframeSlot* s = keyframe_slot(tick);
  if (s == nullptr) return;
  s->bytes.assign(checkpoint.begin(), checkpoint.end());
  publish_keyframe(t0);
}

void MatchLogWriter::append_keyframe_swap(std::uint64_t tick, std::vector<std::uint8_t>& checkpoint) {
  const Clock::time_point t0 = Clock::now();
  KeyframeSlot* s = keyframe_slot(tick);
  if (s == nullptr) return;
  s->bytes.swap(checkpoint);
  publish_keyframe(t0);
}

bool MatchLogWriter::resolve_keyframe() {
  const std::uint64_t k = kf_pending_;
  // Decided once the tick thread has moved past tick k (appended k + 1, or is closing): anything it
  // appended for k is in the slots by then (release/acquire on appended_ and kf_head_).
  const bool final = base_tick_ + appended_.load(std::memory_order_acquire) > k || closing_.load(std::memory_order_acquire);
  for (;;) {
    const std::uint64_t t = kf_tail_.load(std::memory_order_relaxed);
    if (t == kf_head_.load(std::memory_order_acquire)) break;
    KeyframeSlot& s = kf_ring_[t % kf_ring_.size()];
    if (s.tick > k) break;  // a later tick's: k has none
    if (s.tick == k) write_keyframe(s.tick, s.bytes);
    else kf_dropped_.fetch_add(1, std::memory_order_relaxed);  // older than its block: cannot be placed
    kf_tail_.store(t + 1, std::memory_order_release);
    if (s.tick == k) {
      kf_pending_ = 0;
      break;
    }
  }
  if (kf_pending_ != 0 && !final) return false;  // the keyframe for k may still come
  kf_pending_ = 0;
  if (opt_.index_interval_ticks > 0 && k % opt_.index_interval_ticks == 0) write_index(false);
  return true;
}

void MatchLogWriter::write_keyframe(std::uint64_t tick, const std::vector<std::uint8_t>& bytes) {
  if (io_failed_.load(std::memory_order_relaxed)) {
    kf_dropped_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  kf_payload_.clear();
  ByteWriter(kf_payload_).put<std::uint64_t>(tick);
  detail::append_body(zctx_, opt_.zstd_level, bytes, compressed_, kf_payload_);
  const std::uint64_t at = offset_;
  write_record(RecordType::keyframe, kf_payload_);
  if (io_failed_.load(std::memory_order_relaxed)) {
    kf_dropped_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  kf_unpublished_.push_back({tick, at});
  detail::atomic_max(index_held_high_, index_unpublished_.size() + kf_unpublished_.size());
  kf_written_.fetch_add(1, std::memory_order_relaxed);
  kf_bytes_.fetch_add(offset_ - at, std::memory_order_relaxed);
  kf_raw_bytes_.fetch_add(bytes.size(), std::memory_order_relaxed);
}

}  // namespace throng::matchlog
