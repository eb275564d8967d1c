#include "throng/server/memory_trimmer.h"

#include <malloc.h>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace throng::server {

void trim_malloc_heap() { malloc_trim(0); }

MemoryTrimmer::MemoryTrimmer(std::chrono::milliseconds interval, std::function<void()> trim)
    : interval_(interval), trim_(std::move(trim)) {
  if (interval_.count() <= 0) throw std::invalid_argument("MemoryTrimmer: the interval must be positive");
  if (!trim_) throw std::invalid_argument("MemoryTrimmer: no trim function");
  thread_ = std::thread([this] { run(); });
}

std::unique_ptr<MemoryTrimmer> MemoryTrimmer::every_seconds(double seconds) {
  if (seconds == 0.0) return nullptr;
  if (!(seconds >= kMinSeconds && seconds <= kMaxSeconds))  // NaN fails both
    throw std::invalid_argument("MemoryTrimmer: the interval must be 0 (never) or from 0.1 to 86400 s");
  return std::make_unique<MemoryTrimmer>(std::chrono::milliseconds(std::llround(seconds * 1e3)));
}

MemoryTrimmer::~MemoryTrimmer() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

MemoryTrimmer::Stats MemoryTrimmer::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void MemoryTrimmer::run() {
  using Clock = std::chrono::steady_clock;
  std::unique_lock lock(mutex_);
  for (;;) {
    if (cv_.wait_for(lock, interval_, [this] { return stopping_; })) return;
    lock.unlock();  // stats() and the destructor must not wait for a trim
    const auto t0 = Clock::now();
    trim_();
    const double took = std::chrono::duration<double>(Clock::now() - t0).count();
    lock.lock();
    ++stats_.trims;
    stats_.total_seconds += took;
    stats_.max_seconds = std::max(stats_.max_seconds, took);
  }
}

void log_and_stop(std::unique_ptr<MemoryTrimmer>& trimmer) {
  if (!trimmer) return;
  const MemoryTrimmer::Stats ts = trimmer->stats();
  const double every_s = static_cast<double>(trimmer->interval().count()) / 1e3;
  trimmer.reset();
  spdlog::info("memory trims: {} (every {} s), {:.3f} ms on average, {:.3f} ms the longest", ts.trims, every_s,
               ts.trims ? ts.total_seconds / static_cast<double>(ts.trims) * 1e3 : 0.0, ts.max_seconds * 1e3);
}

}  // namespace throng::server
