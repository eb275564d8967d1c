#pragma once
// Gives the memory malloc holds freed back to the system, every interval, on a thread of its own.
//
// Why: glibc hands a heap's free pages back only from its top. A block freed below a longer-lived
// one stays resident, reused only by requests it fits. Over a long match, clients come and go
// (their snapshot state, Fast DDS's per-writer buffers) and the log's blocks grow with the battle,
// and those holes keep the server's resident memory creeping up after its working set has stopped
// growing (docs/design/memory.md). malloc_trim(0) returns every whole free page of every arena.
//
// Why a thread of its own: a trim holds each arena's lock while it walks that arena's free lists,
// and a thread allocating in that arena meanwhile waits. The trim is not the tick's work, and the
// tick thread allocates nothing in the world's step after warm-up.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

namespace throng::server {

// malloc_trim(0): what the server's trimmer calls.
void trim_malloc_heap();

class MemoryTrimmer {
 public:
  struct Stats {
    std::uint64_t trims = 0;
    double total_seconds = 0.0;  // time spent trimming, summed
    double max_seconds = 0.0;    // the longest trim
  };

  // Calls `trim` every `interval` (> 0) until destroyed. `trim` runs on the trimmer's thread and
  // must not throw (an exception there would end the process).
  explicit MemoryTrimmer(std::chrono::milliseconds interval, std::function<void()> trim = trim_malloc_heap);
  ~MemoryTrimmer();  // stops the thread; a trim in progress finishes first
  MemoryTrimmer(const MemoryTrimmer&) = delete;
  MemoryTrimmer& operator=(const MemoryTrimmer&) = delete;

  Stats stats() const;
  std::chrono::milliseconds interval() const { return interval_; }

  // The servers' trimmer: malloc_trim every `seconds` (rounded to whole milliseconds); null for 0
  // (--trim-memory-every 0: never). Below kMinSeconds or above kMaxSeconds, NaN or infinite:
  // std::invalid_argument. Why a floor: a trim holds the arenas' locks for up to about a
  // millisecond, so trimming every few milliseconds would keep them held much of the time.
  static constexpr double kMinSeconds = 0.1, kMaxSeconds = 86400.0;
  static std::unique_ptr<MemoryTrimmer> every_seconds(double seconds);

 private:
  void run();

  const std::chrono::milliseconds interval_;
  const std::function<void()> trim_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  bool stopping_ = false;
  Stats stats_;
  std::thread thread_;
};

// Stops the trimmer (if any) and logs how many trims it made and how long they took.
void log_and_stop(std::unique_ptr<MemoryTrimmer>& trimmer);

}  // namespace throng::server
