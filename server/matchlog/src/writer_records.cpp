// Records on disk: tick blocks, gaps and index records framed and written, with bounded
// fdatasync and the first I/O error kept (the match goes on; the log stops).
#include "throng/matchlog/writer.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <thread>

#include <fmt/format.h>

#include "throng/core/byte_io.h"
#include "writer_io.h"

namespace throng::matchlog {

using Clock = detail::WriterClock;

void MatchLogWriter::flush_block() {
  if (block_count_ == 0 || io_failed_.load(std::memory_order_relaxed)) return;
  block_payload_.clear();
  ByteWriter w(block_payload_);
  w.put<std::uint64_t>(block_first_);
  w.put<std::uint32_t>(static_cast<std::uint32_t>(block_count_));
  detail::append_body(zctx_, opt_.zstd_level, block_raw_, compressed_, block_payload_);
  index_all_.push_back({block_first_, offset_, static_cast<std::uint32_t>(block_count_)});
  write_record(RecordType::tick_block, block_payload_);
  if (io_failed_.load(std::memory_order_relaxed)) {
    index_all_.pop_back();
    dropped_.fetch_add(block_count_, std::memory_order_relaxed);
  } else {
    written_.fetch_add(block_count_, std::memory_order_relaxed);
    raw_bytes_.fetch_add(block_raw_.size(), std::memory_order_relaxed);
  }
  block_raw_.clear();
  block_count_ = 0;
}

void MatchLogWriter::write_gap(std::uint64_t first, std::uint64_t count, std::uint8_t reason) {
  std::vector<std::uint8_t> p;
  ByteWriter w(p);
  w.put<std::uint64_t>(first);
  w.put<std::uint64_t>(count);
  w.put<std::uint8_t>(reason);
  write_record(RecordType::gap, p);
}

void MatchLogWriter::write_index(bool final) {
  const std::size_t from = final ? 0 : index_published_;
  std::vector<std::uint8_t> p;
  ByteWriter w(p);
  w.put<std::uint64_t>(last_index_offset_);
  w.put<std::uint8_t>(final ? 1 : 0);
  w.put<std::uint32_t>(static_cast<std::uint32_t>(index_all_.size() - from));
  for (std::size_t i = from; i < index_all_.size(); ++i) {
    w.put<std::uint64_t>(index_all_[i].first_tick);
    w.put<std::uint32_t>(index_all_[i].tick_count);
    w.put<std::uint64_t>(index_all_[i].offset);
  }
  // v2: the keyframes since the previous index (final: all of them).
  const std::size_t kfrom = final ? 0 : kf_published_;
  w.put<std::uint32_t>(static_cast<std::uint32_t>(kf_all_.size() - kfrom));
  for (std::size_t i = kfrom; i < kf_all_.size(); ++i) {
    w.put<std::uint64_t>(kf_all_[i].tick);
    w.put<std::uint64_t>(kf_all_[i].offset);
  }
  kf_published_ = kf_all_.size();
  last_index_offset_ = offset_;
  index_published_ = index_all_.size();
  write_record(RecordType::index, p);
}

void MatchLogWriter::write_record(RecordType type, const std::vector<std::uint8_t>& payload) {
  if (io_failed_.load(std::memory_order_relaxed)) return;
  record_.clear();
  detail::frame_record(type, payload, record_);
  const std::string err = detail::write_all(fd_, record_.data(), record_.size());
  if (!err.empty()) {
    fail_io(fmt::format("write of a {} record at byte {} failed: {}", to_string(type), offset_, err));
    return;
  }
  offset_ += record_.size();
  unsynced_bytes_ += record_.size();
  bytes_.store(offset_, std::memory_order_relaxed);
  records_.fetch_add(1, std::memory_order_relaxed);
  if (opt_.test_write_delay_ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(opt_.test_write_delay_ms));
  maybe_fsync(opt_.fsync_interval_ms == 0);
}

void MatchLogWriter::maybe_fsync(bool force) {
  if (unsynced_bytes_ == 0 || io_failed_.load(std::memory_order_relaxed)) return;
  const Clock::time_point now = Clock::now();
  if (!force && now - last_sync_ < std::chrono::milliseconds(opt_.fsync_interval_ms)) return;
  if (::fdatasync(fd_) != 0) {
    fail_io(fmt::format("fdatasync at byte {} failed: {}", offset_, std::strerror(errno)));
    return;
  }
  const Clock::time_point done = Clock::now();
  detail::atomic_max(max_fsync_ns_, detail::ns_between(now, done));
  fsyncs_.fetch_add(1, std::memory_order_relaxed);
  unsynced_bytes_ = 0;
  last_sync_ = done;
}

void MatchLogWriter::fail_io(const std::string& what) {
  {
    std::lock_guard<std::mutex> lock(error_mutex_);
    if (io_error_.empty()) io_error_ = what;
  }
  io_failed_.store(true, std::memory_order_relaxed);
}

}  // namespace throng::matchlog
