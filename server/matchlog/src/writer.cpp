// MatchLogWriter: a single-producer ring of pre-allocated tick slots (tick thread -> writer
// thread), a capped spill list behind it, and a writer thread that blocks, compresses, frames,
// writes and fsyncs. See writer.h for the contract and FORMAT.md for the bytes.
#include "throng/matchlog/writer.h"

#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>
#include <zstd.h>

#include "byte_io.h"
#include "throng/matchlog/crc32c.h"
#include "throng/matchlog/tick_record.h"

namespace throng::matchlog {
namespace {

using Clock = std::chrono::steady_clock;

std::uint64_t ns_between(Clock::time_point a, Clock::time_point b) {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(b - a).count());
}

void atomic_max(std::atomic<std::uint64_t>& a, std::uint64_t v) {
  std::uint64_t cur = a.load(std::memory_order_relaxed);
  while (v > cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}

// write(2) until everything is written; "" or the error.
std::string write_all(int fd, const std::uint8_t* p, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return std::strerror(errno);
    }
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  return {};
}

std::vector<std::uint8_t> frame(RecordType type, const std::vector<std::uint8_t>& payload) {
  std::vector<std::uint8_t> r;
  r.reserve(payload.size() + kRecordOverheadBytes);
  detail::put_u32(r, static_cast<std::uint32_t>(payload.size()));
  detail::put_u8(r, static_cast<std::uint8_t>(type));
  r.insert(r.end(), payload.begin(), payload.end());
  detail::put_u32(r, crc32c(r.data(), r.size()));
  return r;
}

}  // namespace

MatchLogWriter::MatchLogWriter(std::string path, WriterOptions options) : path_(std::move(path)), opt_(options) {}

MatchLogWriter::~MatchLogWriter() {
  try {
    close();
  } catch (...) {  // the destructor cannot report; close() explicitly to see errors
  }
}

void MatchLogWriter::begin(LogHeader header) {
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

  header.format_version = kFormatVersion;
  if (header.build_id.empty()) header.build_id = default_build_id();
  header.scene = self_contained_scene(header.scene);
  header.start_unix_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                             std::chrono::system_clock::now().time_since_epoch()).count();
  header.start_utc = format_utc_ms(header.start_unix_ms);
  header.writer = {opt_.block_ticks, opt_.index_interval_ticks, opt_.fsync_interval_ms, opt_.zstd_level,
                   opt_.keyframe_interval_ticks, opt_.keyframe_snapshot_baselines};
  const std::string text = header_to_json_text(header);

  const std::filesystem::path p(path_);
  std::error_code ec;
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path(), ec);
  if (ec) throw LogError(fmt::format("match log {}: cannot create folder {}: {}", path_, p.parent_path().string(), ec.message()));
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw LogError(fmt::format("match log {}: cannot create: {}", path_, std::strerror(errno)));

  std::vector<std::uint8_t> pre(kMagic, kMagic + 8);
  detail::put_u32(pre, kFormatVersion);
  std::vector<std::uint8_t> payload(text.begin(), text.end());
  const std::vector<std::uint8_t> rec = frame(RecordType::header, payload);
  pre.insert(pre.end(), rec.begin(), rec.end());
  std::string err = write_all(fd_, pre.data(), pre.size());
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
  began_ = true;
  thread_ = std::thread([this] { run(); });
  // SCHED_BATCH: the writer never preempts the tick thread when its timer wakes it (it still gets
  // its share of the CPU, which is far more than it needs). Not fatal if refused.
  sched_param sp{};
  sp.sched_priority = 0;
  pthread_setschedparam(thread_.native_handle(), SCHED_BATCH, &sp);
}

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
  atomic_max(backlog_high_, backlog);
  // No notify here: waking the writer thread from the tick thread lets the scheduler run the
  // writer (zstd of a whole block) on this core right away and preempt the tick, which showed in
  // the append's p99 (docs/design/match-log.md). The writer polls every poll_ms instead.

  const std::uint64_t ns = ns_between(t0, Clock::now());
  atomic_max(max_append_ns_, ns);
  const std::size_t bin = static_cast<std::size_t>(ns / 100);
  if (bin < kHistBins) hist_[bin].fetch_add(1, std::memory_order_relaxed);
  else hist_over_.fetch_add(1, std::memory_order_relaxed);
}

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
  atomic_max(max_kf_append_ns_, ns_between(t0, Clock::now()));
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
  const bool final = appended_.load(std::memory_order_acquire) > k || closing_.load(std::memory_order_acquire);
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
  detail::put_u64(kf_payload_, tick);
  BlockCodec codec = BlockCodec::raw;
  if (zctx_ != nullptr) {
    compressed_.resize(ZSTD_compressBound(bytes.size()));
    const std::size_t n = ZSTD_compressCCtx(static_cast<ZSTD_CCtx*>(zctx_), compressed_.data(), compressed_.size(),
                                            bytes.data(), bytes.size(), opt_.zstd_level);
    if (!ZSTD_isError(n) && n < bytes.size()) {
      compressed_.resize(n);
      codec = BlockCodec::zstd;
    }
  }
  detail::put_u8(kf_payload_, static_cast<std::uint8_t>(codec));
  detail::put_u32(kf_payload_, static_cast<std::uint32_t>(bytes.size()));
  const std::vector<std::uint8_t>& body = codec == BlockCodec::zstd ? compressed_ : bytes;
  kf_payload_.insert(kf_payload_.end(), body.begin(), body.end());
  const std::uint64_t at = offset_;
  write_record(RecordType::keyframe, kf_payload_);
  if (io_failed_.load(std::memory_order_relaxed)) {
    kf_dropped_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  kf_all_.push_back({tick, at});
  kf_written_.fetch_add(1, std::memory_order_relaxed);
  kf_bytes_.fetch_add(offset_ - at, std::memory_order_relaxed);
  kf_raw_bytes_.fetch_add(bytes.size(), std::memory_order_relaxed);
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
  const std::uint64_t tick = detail::load_u64(entry.data());
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

void MatchLogWriter::flush_block() {
  if (block_count_ == 0 || io_failed_.load(std::memory_order_relaxed)) return;
  block_payload_.clear();
  detail::put_u64(block_payload_, block_first_);
  detail::put_u32(block_payload_, static_cast<std::uint32_t>(block_count_));
  BlockCodec codec = BlockCodec::raw;
  if (zctx_ != nullptr) {
    compressed_.resize(ZSTD_compressBound(block_raw_.size()));
    const std::size_t n = ZSTD_compressCCtx(static_cast<ZSTD_CCtx*>(zctx_), compressed_.data(), compressed_.size(),
                                            block_raw_.data(), block_raw_.size(), opt_.zstd_level);
    if (!ZSTD_isError(n) && n < block_raw_.size()) {
      compressed_.resize(n);
      codec = BlockCodec::zstd;
    }
  }
  detail::put_u8(block_payload_, static_cast<std::uint8_t>(codec));
  detail::put_u32(block_payload_, static_cast<std::uint32_t>(block_raw_.size()));
  const std::vector<std::uint8_t>& body = codec == BlockCodec::zstd ? compressed_ : block_raw_;
  block_payload_.insert(block_payload_.end(), body.begin(), body.end());
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

void MatchLogWriter::write_gap(std::uint64_t first, std::uint64_t count) {
  std::vector<std::uint8_t> p;
  detail::put_u64(p, first);
  detail::put_u64(p, count);
  detail::put_u8(p, 1);  // reason: the writer's backlog exceeded its cap
  write_record(RecordType::gap, p);
}

void MatchLogWriter::write_index(bool final) {
  const std::size_t from = final ? 0 : index_published_;
  std::vector<std::uint8_t> p;
  detail::put_u64(p, last_index_offset_);
  detail::put_u8(p, final ? 1 : 0);
  detail::put_u32(p, static_cast<std::uint32_t>(index_all_.size() - from));
  for (std::size_t i = from; i < index_all_.size(); ++i) {
    detail::put_u64(p, index_all_[i].first_tick);
    detail::put_u32(p, index_all_[i].tick_count);
    detail::put_u64(p, index_all_[i].offset);
  }
  // v2: the keyframes since the previous index (final: all of them).
  const std::size_t kfrom = final ? 0 : kf_published_;
  detail::put_u32(p, static_cast<std::uint32_t>(kf_all_.size() - kfrom));
  for (std::size_t i = kfrom; i < kf_all_.size(); ++i) {
    detail::put_u64(p, kf_all_[i].tick);
    detail::put_u64(p, kf_all_[i].offset);
  }
  kf_published_ = kf_all_.size();
  last_index_offset_ = offset_;
  index_published_ = index_all_.size();
  write_record(RecordType::index, p);
}

void MatchLogWriter::write_record(RecordType type, const std::vector<std::uint8_t>& payload) {
  if (io_failed_.load(std::memory_order_relaxed)) return;
  record_.clear();
  detail::put_u32(record_, static_cast<std::uint32_t>(payload.size()));
  detail::put_u8(record_, static_cast<std::uint8_t>(type));
  record_.insert(record_.end(), payload.begin(), payload.end());
  detail::put_u32(record_, crc32c(record_.data(), record_.size()));
  const std::string err = write_all(fd_, record_.data(), record_.size());
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
  atomic_max(max_fsync_ns_, ns_between(now, done));
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
  const std::uint64_t last = appended_.load(std::memory_order_relaxed);
  if (expected_tick_ <= last) write_gap(expected_tick_, last - expected_tick_ + 1);  // dropped at the very end
  const std::uint64_t index_offset = offset_;
  write_index(true);
  std::vector<std::uint8_t> p;
  detail::put_u64(p, index_offset);
  detail::put_u64(p, last);
  detail::put_u64(p, written_.load(std::memory_order_relaxed));
  detail::put_u64(p, dropped_.load(std::memory_order_relaxed));
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
  std::lock_guard<std::mutex> lock(error_mutex_);
  s.io_error = io_error_;
  return s;
}

}  // namespace throng::matchlog
