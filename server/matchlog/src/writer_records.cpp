// Records on disk: tick blocks, gaps and index records framed and written, with bounded
// fdatasync and the first I/O error kept (the match goes on; the log stops).
#include "throng/matchlog/writer.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <thread>

#include <fmt/format.h>

#include "record_framing.h"
#include "throng/core/byte_io.h"
#include "throng/matchlog/format.h"
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
  index_unpublished_.push_back({block_first_, offset_, static_cast<std::uint32_t>(block_count_)});
  detail::atomic_max(index_held_high_, index_unpublished_.size() + kf_unpublished_.size());
  write_record(RecordType::tick_block, block_payload_);
  if (io_failed_.load(std::memory_order_relaxed)) {
    index_unpublished_.pop_back();
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

// A periodic index lists the blocks and keyframes since the previous one; the final index lists
// them all, the earlier ones read back from the periodic records in the file.
void MatchLogWriter::write_index(bool final) {
  std::vector<IndexEntry> read_back;
  std::vector<KeyframeEntry> kf_read_back;
  if (final && !read_published_index(read_back, kf_read_back)) return;
  std::vector<std::uint8_t> p;
  ByteWriter w(p);
  w.put<std::uint64_t>(last_index_offset_);
  w.put<std::uint8_t>(final ? 1 : 0);
  w.put<std::uint32_t>(static_cast<std::uint32_t>(read_back.size() + index_unpublished_.size()));
  for (const std::vector<IndexEntry>* part : {&read_back, &index_unpublished_}) {
    for (const IndexEntry& e : *part) {
      w.put<std::uint64_t>(e.first_tick);
      w.put<std::uint32_t>(e.tick_count);
      w.put<std::uint64_t>(e.offset);
    }
  }
  // v2: the keyframes since the previous index (final: all of them).
  w.put<std::uint32_t>(static_cast<std::uint32_t>(kf_read_back.size() + kf_unpublished_.size()));
  for (const std::vector<KeyframeEntry>* part : {&kf_read_back, &kf_unpublished_}) {
    for (const KeyframeEntry& e : *part) {
      w.put<std::uint64_t>(e.tick);
      w.put<std::uint64_t>(e.offset);
    }
  }
  index_unpublished_.clear();
  kf_unpublished_.clear();
  last_index_offset_ = offset_;
  write_record(RecordType::index, p);
}

// The entries of every periodic index record written so far, oldest first: each record starts
// with the offset of the one before it (0 for the first). False (the I/O error recorded) if one
// cannot be read back whole and intact; the log then ends without a final index, as after a crash,
// and readers recover it by scanning.
bool MatchLogWriter::read_published_index(std::vector<IndexEntry>& blocks, std::vector<KeyframeEntry>& keyframes) {
  std::vector<std::vector<std::uint8_t>> records;  // newest first
  for (std::uint64_t at = last_index_offset_; at != 0;) {
    std::vector<std::uint8_t> rec(kRecordOverheadBytes);
    std::string err = detail::read_all_at(fd_, rec.data(), 5, at);
    if (err.empty()) {
      rec.resize(kRecordOverheadBytes + load_bytes<std::uint32_t>(rec.data()));
      if (rec.size() > offset_ - at) err = "its length runs past the end of the file";
    }
    if (err.empty()) err = detail::read_all_at(fd_, rec.data(), rec.size(), at);
    if (err.empty()) {
      const detail::RecordCheck check = detail::check_record(rec.data(), rec.size(), 0);
      if (!check.ok) err = check.why;
      else if (check.type != static_cast<std::uint8_t>(RecordType::index)) err = "not an index record";
      else err = detail::index_counts(rec.data() + 5, check.length, kFormatVersion).why;
    }
    const std::uint64_t before = err.empty() ? load_bytes<std::uint64_t>(rec.data() + 5) : 0;
    if (err.empty() && before >= at) err = "it does not point backwards";
    if (!err.empty()) {
      fail_io(fmt::format("reading back the index record at byte {} for the final index: {}", at, err));
      return false;
    }
    records.push_back(std::move(rec));
    at = before;
  }
  // Each record as write_index wrote it (index_counts checked its layout above).
  for (auto r = records.rbegin(); r != records.rend(); ++r) {
    const std::uint8_t* p = r->data() + 5;
    const detail::IndexCounts counts = detail::index_counts(p, static_cast<std::uint32_t>(r->size() - kRecordOverheadBytes), kFormatVersion);
    const std::uint8_t* e = p + 13;
    for (std::uint32_t k = 0; k < counts.blocks; ++k, e += 20)
      blocks.push_back({load_bytes<std::uint64_t>(e), load_bytes<std::uint64_t>(e + 12), load_bytes<std::uint32_t>(e + 8)});
    e = p + counts.keyframe_part;
    for (std::uint32_t k = 0; k < counts.keyframes; ++k, e += 16)
      keyframes.push_back({load_bytes<std::uint64_t>(e), load_bytes<std::uint64_t>(e + 8)});
  }
  return true;
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
