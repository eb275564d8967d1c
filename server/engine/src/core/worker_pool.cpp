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

// A few thousand pause instructions (tens to a couple of hundred microseconds, by CPU): long
// enough to catch the next phase of the same solve, short enough that a pool idle between ticks
// sleeps instead of burning a core.
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
  tasks_.store(tasks, std::memory_order_relaxed);
  completed_.store(0, std::memory_order_relaxed);
  const std::uint64_t run = generation_.load(std::memory_order_relaxed) + 1;
  next_.store(((run & 0xFFFFFFFFu) << 32) | tasks, std::memory_order_release);
  generation_.store(run, std::memory_order_release);
  generation_.notify_all();
}

// The low half of next_ counts the tasks left, not the next index: a claim must not depend on
// anything but next_ itself. With an index compared against tasks_, a thread that had read the
// last run's exhausted next_ and then the next run's (larger) tasks_, published first, could take
// a task of the new run with the old next_ still in place, before the new run began.
bool WorkerPool::claim(std::uint64_t run, std::uint32_t& task) {
  std::uint64_t v = next_.load(std::memory_order_acquire);
  for (;;) {
    if ((v >> 32) != (run & 0xFFFFFFFFu)) return false;  // that run is over
    const auto left = static_cast<std::uint32_t>(v);
    if (left == 0) return false;
    if (next_.compare_exchange_weak(v, v - 1, std::memory_order_acq_rel, std::memory_order_acquire)) {
      // tasks_ is this run's: it was stored before next_ was published, and cannot change before
      // the task claimed here completes.
      task = tasks_.load(std::memory_order_relaxed) - left;
      return true;
    }
  }
}

void WorkerPool::drain(std::uint64_t run, unsigned thread) {
  std::uint32_t task = 0;
  while (claim(run, task)) {
    job_(ctx_, task, thread);
    completed_.fetch_add(1, std::memory_order_release);
  }
}

void WorkerPool::finish() {
  const std::uint64_t run = generation_.load(std::memory_order_relaxed);
  drain(run, 0);
  // The tasks other threads claimed complete; their writes are visible after this acquire.
  const std::uint32_t tasks = tasks_.load(std::memory_order_relaxed);
  for (int spin = 0; completed_.load(std::memory_order_acquire) != tasks;) {
    if (spin < kSpinRounds) {
      cpu_relax();
      ++spin;
    } else {
      std::this_thread::yield();  // a thread lost its core mid-task: let it have ours
    }
  }
}

void WorkerPool::worker_loop(unsigned thread) {
  std::uint64_t seen = 0;
  for (;;) {
    std::uint64_t g = generation_.load(std::memory_order_acquire);
    for (int spin = 0; g == seen;) {
      if (spin < kSpinRounds) {
        cpu_relax();
        ++spin;
      } else {
        generation_.wait(seen, std::memory_order_acquire);
      }
      g = generation_.load(std::memory_order_acquire);
    }
    seen = g;
    if (stop_.load(std::memory_order_relaxed)) return;
    drain(g, thread);
  }
}

}  // namespace throng
