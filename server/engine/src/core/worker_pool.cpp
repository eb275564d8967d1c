#include "throng/core/worker_pool.h"

#include <stdexcept>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace throng {
namespace {

inline void cpu_relax() {
#if defined(__SSE2__)
  _mm_pause();
#endif
}

// About 10-50 microseconds of pause instructions: long enough to catch the next phase of the same
// solve, short enough that a pool idle between ticks sleeps instead of burning a core.
constexpr int kSpinRounds = 4096;

}  // namespace

WorkerPool::WorkerPool(unsigned threads) {
  if (threads < 1 || threads > kMaxThreads) {
    throw std::invalid_argument("worker pool: threads = " + std::to_string(threads) + " is outside [1, " +
                                std::to_string(kMaxThreads) + "]");
  }
  workers_.reserve(threads - 1);
  for (unsigned i = 1; i < threads; ++i) workers_.emplace_back([this, i] { worker_loop(i); });
}

WorkerPool::~WorkerPool() {
  stop_.store(true, std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void WorkerPool::start(std::uint32_t tasks, Job job, void* ctx) {
  job_ = job;
  ctx_ = ctx;
  tasks_ = tasks;
  next_.store(0, std::memory_order_relaxed);
  done_.store(0, std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
}

void WorkerPool::drain(unsigned thread) {
  for (;;) {
    const std::uint32_t t = next_.fetch_add(1, std::memory_order_relaxed);
    if (t >= tasks_) return;
    job_(ctx_, t, thread);

  }
}

void WorkerPool::finish() {
  drain(0);
  // The others finish the tasks they took; their writes are visible after this acquire.
  const std::uint32_t workers = static_cast<std::uint32_t>(workers_.size());
  for (int spin = 0; done_.load(std::memory_order_acquire) != workers; ++spin) {
    if (spin < kSpinRounds) cpu_relax();
    else std::this_thread::yield();  // a worker lost its core: let it have ours
  }
}

void WorkerPool::worker_loop(unsigned thread) {
  std::uint64_t seen = 0;
  for (;;) {
    std::uint64_t g = generation_.load(std::memory_order_acquire);
    for (int spin = 0; g == seen; ++spin) {
      if (spin < kSpinRounds) cpu_relax();
      else generation_.wait(seen, std::memory_order_acquire);
      g = generation_.load(std::memory_order_acquire);
    }
    seen = g;
    if (stop_.load(std::memory_order_relaxed)) return;
    drain(thread);
    done_.fetch_add(1, std::memory_order_release);
  }
}

}  // namespace throng
