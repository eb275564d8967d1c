// MatchLogWriter's life cycle: options checked and the header written durably (begin), the writer
// thread's loop and the file's clean end (run, close), and the counters (stats). The writer as a
// whole: a single-producer ring of pre-allocated tick slots (tick thread -> writer thread), a
// capped spill list behind it, and a writer thread that compresses, frames, writes and fsyncs.
// Its other parts: writer_tick_queue.cpp, writer_keyframes.cpp, writer_records.cpp. See writer.h
// for the contract and FORMAT.md for the bytes.
#include "throng/matchlog/writer.h"

#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>
#include <zstd.h>

#include "throng/core/byte_io.h"
#include "writer_io.h"

namespace throng::matchlog {

using Clock = detail::WriterClock;

MatchLogWriter::MatchLogWriter(std::string path, WriterOptions options) : path_(std::move(path)), opt_(options) {}

MatchLogWriter::~MatchLogWriter() {
  try {
    close();
  } catch (...) {  // the destructor cannot report; close() explicitly to see errors
  }
}

void MatchLogWriter::begin(LogHeader header) { start(std::move(header), 0, nullptr); }

void MatchLogWriter::begin_from(LogHeader header, std::uint64_t tick, const std::vector<std::uint8_t>& checkpoint) {
  if (tick == 0) throw LogError("match log " + path_ + ": begin_from() needs a tick >= 1 (begin() starts before tick 1)");
  start(std::move(header), tick, &checkpoint);
}

void MatchLogWriter::start(LogHeader header, std::uint64_t base_tick, const std::vector<std::uint8_t>* checkpoint) {
  if (began_) throw LogError("match log " + path_ + ": begin() called twice");
  if (opt_.block_ticks < 1 || opt_.block_ticks > 4096) throw LogError("match log: block_ticks must be in [1, 4096]");
  if (opt_.zstd_level < 0 || opt_.zstd_level > 19) throw LogError("match log: zstd_level must be in [0, 19]");
  if (opt_.ring_slots < 2) throw LogError("match log: ring_slots must be >= 2");
  if (opt_.index_interval_ticks > 0) {
    const std::uint32_t b = opt_.block_ticks;
    opt_.index_interval_ticks = (opt_.index_interval_ticks + b - 1) / b * b;
  }
  if (opt_.keyframe_interval_ticks > 0) {
    const std::uint32_t b = opt_.block_ticks;
    opt_.keyframe_interval_ticks = (opt_.keyframe_interval_ticks + b - 1) / b * b;
    if (opt_.keyframe_slots < 1) throw LogError("match log: keyframe_slots must be >= 1");
  }

  header = stamp_header(std::move(header));
  header.writer = {opt_.block_ticks, opt_.index_interval_ticks, opt_.fsync_interval_ms, opt_.zstd_level,
                   opt_.keyframe_interval_ticks, opt_.keyframe_snapshot_baselines};
  const std::string text = header_to_json_text(header);

  const std::filesystem::path p(path_);
  std::error_code ec;
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path(), ec);
  if (ec) throw LogError(fmt::format("match log {}: cannot create folder {}: {}", path_, p.parent_path().string(), ec.message()));
  // Read as well: the final index reads the periodic index records back (read_published_index).
  fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw LogError(fmt::format("match log {}: cannot create: {}", path_, std::strerror(errno)));

  std::vector<std::uint8_t> pre(kMagic, kMagic + 8);
  ByteWriter(pre).put<std::uint32_t>(kFormatVersion);
  std::vector<std::uint8_t> rec;
  detail::frame_record(RecordType::header, std::vector<std::uint8_t>(text.begin(), text.end()), rec);
  pre.insert(pre.end(), rec.begin(), rec.end());
  std::string err = detail::write_all(fd_, pre.data(), pre.size());
  if (err.empty() && ::fdatasync(fd_) != 0) err = std::strerror(errno);
  if (!err.empty()) {
    ::close(fd_);
    fd_ = -1;
    throw LogError(fmt::format("match log {}: cannot write the header: {}", path_, err));
  }
  // The file's directory entry must survive a power loss too.
  const std::string dir = p.has_parent_path() ? p.parent_path().string() : ".";
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
  offset_ = pre.size();
  bytes_ = offset_;
  records_ = 1;
  fsyncs_ = 1;

  ring_.resize(opt_.ring_slots);
  kf_ring_.resize(opt_.keyframe_interval_ticks > 0 ? opt_.keyframe_slots : 0);
  for (Slot& s : ring_) s.bytes.reserve(opt_.slot_reserve_bytes);
  hist_ = std::make_unique<std::atomic<std::uint32_t>[]>(kHistBins);
  for (std::size_t i = 0; i < kHistBins; ++i) hist_[i].store(0, std::memory_order_relaxed);
  block_raw_.reserve(opt_.block_ticks * opt_.slot_reserve_bytes);
  if (opt_.zstd_level > 0) zctx_ = ZSTD_createCCtx();
  last_sync_ = Clock::now();
  if (base_tick > 0) {
    // Before the writer thread exists, on this thread: the start is in the file when this returns.
    write_gap(1, base_tick, kGapStartedFromCheckpoint);
    write_keyframe(base_tick, *checkpoint);
    maybe_fsync(true);
    {
      std::lock_guard<std::mutex> lock(error_mutex_);
      if (!io_error_.empty()) throw LogError(fmt::format("match log {}: cannot write its start: {}", path_, io_error_));
    }
    base_tick_ = base_tick;
    next_tick_ = base_tick + 1;
    expected_tick_ = base_tick + 1;
  }
  began_ = true;
  thread_ = std::thread([this] { run(); });
  // SCHED_BATCH: the writer never preempts the tick thread when its timer wakes it (it still gets
  // its share of the CPU, which is far more than it needs). Not fatal if refused.
  sched_param sp{};
  sp.sched_priority = 0;
  pthread_setschedparam(thread_.native_handle(), SCHED_BATCH, &sp);
}

void MatchLogWriter::run() {
  for (;;) {
    while (process_one()) {
    }
    maybe_fsync(false);
    if (closing_.load(std::memory_order_acquire)) {
      // The tick thread has stopped appending: take whatever is left, then finish the file.
      while (process_one()) {
      }
      if (kf_pending_ != 0) resolve_keyframe();  // closing: decided
      break;
    }
    auto timeout = std::chrono::milliseconds(std::max<std::uint32_t>(1, opt_.poll_ms));
    if (unsynced_bytes_ > 0) {
      const auto due = last_sync_ + std::chrono::milliseconds(opt_.fsync_interval_ms);
      timeout = std::clamp(std::chrono::duration_cast<std::chrono::milliseconds>(due - Clock::now()),
                           std::chrono::milliseconds(1), timeout);
    }
    std::unique_lock<std::mutex> lock(wake_mutex_);
    sleeps_.fetch_add(1, std::memory_order_release);
    wake_.wait_for(lock, timeout);
  }
  flush_block();
  const std::uint64_t last = base_tick_ + appended_.load(std::memory_order_relaxed);
  if (expected_tick_ <= last) write_gap(expected_tick_, last - expected_tick_ + 1);  // dropped at the very end
  const std::uint64_t index_offset = offset_;
  write_index(true);
  std::vector<std::uint8_t> p;
  ByteWriter w(p);
  w.put<std::uint64_t>(index_offset);
  w.put<std::uint64_t>(last);
  w.put<std::uint64_t>(written_.load(std::memory_order_relaxed));
  w.put<std::uint64_t>(dropped_.load(std::memory_order_relaxed));
  write_record(RecordType::end, p);
  maybe_fsync(true);
}

void MatchLogWriter::close() {
  if (!began_ || closed_) return;
  {
    std::lock_guard<std::mutex> lock(wake_mutex_);
    closing_.store(true, std::memory_order_release);
  }
  wake_.notify_one();
  thread_.join();
  ::close(fd_);
  fd_ = -1;
  closed_ = true;
  if (zctx_ != nullptr) ZSTD_freeCCtx(static_cast<ZSTD_CCtx*>(zctx_));
  zctx_ = nullptr;
  std::lock_guard<std::mutex> lock(error_mutex_);
  if (!io_error_.empty()) throw LogError("match log " + path_ + ": " + io_error_);
}

WriterStats MatchLogWriter::stats() const {
  WriterStats s;
  s.ticks_appended = appended_.load(std::memory_order_relaxed);
  s.ticks_written = written_.load(std::memory_order_relaxed);
  s.ticks_dropped = dropped_.load(std::memory_order_relaxed);
  const std::uint64_t done = s.ticks_written + s.ticks_dropped;
  s.backlog_ticks = s.ticks_appended > done ? s.ticks_appended - done : 0;
  s.backlog_high_water = backlog_high_.load(std::memory_order_relaxed);
  s.spilled_ticks = spilled_.load(std::memory_order_relaxed);
  s.spill_bytes = spill_bytes_.load(std::memory_order_relaxed);
  s.bytes_written = bytes_.load(std::memory_order_relaxed);
  s.raw_tick_bytes = raw_bytes_.load(std::memory_order_relaxed);
  s.records = records_.load(std::memory_order_relaxed);
  s.fsyncs = fsyncs_.load(std::memory_order_relaxed);
  s.writer_sleeps = sleeps_.load(std::memory_order_acquire);
  s.max_fsync_ms = static_cast<double>(max_fsync_ns_.load(std::memory_order_relaxed)) / 1e6;
  s.max_append_us = static_cast<double>(max_append_ns_.load(std::memory_order_relaxed)) / 1e3;
  if (hist_) {
    std::uint64_t total = hist_over_.load(std::memory_order_relaxed);
    for (std::size_t i = 0; i < kHistBins; ++i) total += hist_[i].load(std::memory_order_relaxed);
    const std::uint64_t want = total - total / 100;  // the 99th percentile's rank
    std::uint64_t seen = 0;
    s.p99_append_us = s.max_append_us;
    for (std::size_t i = 0; i < kHistBins && total > 0; ++i) {
      seen += hist_[i].load(std::memory_order_relaxed);
      if (seen >= want) {
        s.p99_append_us = static_cast<double>(i + 1) * 0.1;
        break;
      }
    }
  }
  s.keyframes_appended = kf_appended_.load(std::memory_order_relaxed);
  s.keyframes_written = kf_written_.load(std::memory_order_relaxed);
  s.keyframes_dropped = kf_dropped_.load(std::memory_order_relaxed);
  s.keyframe_bytes = kf_bytes_.load(std::memory_order_relaxed);
  s.keyframe_raw_bytes = kf_raw_bytes_.load(std::memory_order_relaxed);
  s.max_keyframe_append_us = static_cast<double>(max_kf_append_ns_.load(std::memory_order_relaxed)) / 1e3;
  s.index_entries_high_water = index_held_high_.load(std::memory_order_relaxed);
  std::lock_guard<std::mutex> lock(error_mutex_);
  s.io_error = io_error_;
  return s;
}

}  // namespace throng::matchlog
