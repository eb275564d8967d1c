#pragma once
// A fixed set of threads for the one embarrassingly parallel phase of a tick: building each
// client's snapshot (and, through the sink, publishing it). Work items are handed out through an
// atomic counter, so a slow client does not hold up a whole chunk; results never depend on which
// thread ran an item because every item writes only its own client's state and output slot, and
// per-worker partial statistics are reduced with commutative operations (sum, max) afterwards.
//
// No allocation per run: the job is passed as a function pointer + context, not std::function.
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace throng::match {

class WorkerPool {
 public:
  // threads = total workers including the calling thread (1 = run inline, no threads).
  explicit WorkerPool(unsigned threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  unsigned size() const { return static_cast<unsigned>(threads_.size()) + 1u; }

  // Calls fn(worker, item) for every item in [0, n), worker in [0, size()); returns when all are
  // done. The caller participates as worker 0.
  template <typename F>
  void for_each(std::size_t n, F& fn) {
    run(n, [](void* ctx, unsigned worker, std::size_t item) { (*static_cast<F*>(ctx))(worker, item); }, &fn);
  }

 private:
  using Call = void (*)(void*, unsigned, std::size_t);
  void run(std::size_t n, Call call, void* ctx);
  void work(unsigned worker);
  void drain(unsigned worker);

  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable start_cv_, done_cv_;
  std::uint64_t generation_ = 0;
  unsigned busy_ = 0;
  bool stopping_ = false;
  Call call_ = nullptr;
  void* ctx_ = nullptr;
  std::size_t count_ = 0;
  std::atomic<std::size_t> next_{0};
};

}  // namespace throng::match
