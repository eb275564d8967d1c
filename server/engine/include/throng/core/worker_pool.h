#pragma once
// A small fixed pool of threads: the solve's (WorldSettings::threads) and the match's snapshot
// phase (MatchConfig::worker_threads). run(tasks, fn) calls
// fn(task) once for every task in [0, tasks), on the pool's threads and the caller's, and returns
// when all are done. Tasks are handed out in no fixed order: callers give it only tasks that touch
// disjoint memory, so which thread ran which task never shows in the result.
//
// Why not std::async or a queue of std::function: the solve runs a few dozen parallel phases a
// tick, each a fraction of a millisecond, and the tick must not allocate. A run is a function
// pointer, a context pointer and a task counter; idle threads spin briefly (the next phase usually
// follows within microseconds) and then sleep on the generation counter (a futex on Linux), so a
// pool between ticks costs no CPU.
#include <atomic>
#include <cstdint>
#include <thread>
#include <type_traits>
#include <vector>

namespace throng {

class WorkerPool {
 public:
  // `threads` counts the caller: threads - 1 threads are started. [1, kMaxThreads]
  explicit WorkerPool(unsigned threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  static constexpr unsigned kMaxThreads = 64;

  unsigned threads() const { return static_cast<unsigned>(workers_.size()) + 1; }

  // fn(task), or fn(task, thread) with the running thread's index in [0, threads()) (0: the
  // caller) for per-thread scratch. fn must not throw. Not reentrant: one run at a time, from one
  // caller thread.
  template <class Fn>
  void run(std::uint32_t tasks, Fn& fn) {
    if (workers_.empty() || tasks <= 1) return run_inline(tasks, fn);
    start(tasks, &call<Fn>, &fn);
    finish();
  }

  // Every task in order on the calling thread (as thread 0): what run() does without workers.
  template <class Fn>
  static void run_inline(std::uint32_t tasks, Fn& fn) {
    for (std::uint32_t t = 0; t < tasks; ++t) call<Fn>(&fn, t, 0);
  }

 private:
  using Job = void (*)(void*, std::uint32_t, unsigned);
  template <class Fn>
  static void call(void* ctx, std::uint32_t task, unsigned thread) {
    if constexpr (std::is_invocable_v<Fn&, std::uint32_t, unsigned>) (*static_cast<Fn*>(ctx))(task, thread);
    else (*static_cast<Fn*>(ctx))(task);
  }
  void start(std::uint32_t tasks, Job job, void* ctx);
  void finish();
  bool claim(std::uint64_t run, std::uint32_t& task);
  void drain(std::uint64_t run, unsigned thread);
  void worker_loop(unsigned thread);

  // A run is announced by bumping generation_ (its run number). Tasks are claimed from next_,
  // which holds the run number's low 32 bits above the count of tasks not yet claimed, so a thread
  // that wakes after its run ended claims nothing of the next one. The caller waits for the run's
  // tasks to be completed, not for every thread to check in: a thread still asleep costs the run
  // nothing (the caller and the threads awake take its share).
  // job_ and ctx_ are written before next_ is published and read only after a task of the run
  // is claimed (the run cannot end, and the next cannot start, before that task completes).
  Job job_ = nullptr;
  void* ctx_ = nullptr;
  std::atomic<std::uint32_t> tasks_{0};
  alignas(64) std::atomic<std::uint64_t> generation_{0};
  alignas(64) std::atomic<std::uint64_t> next_{0};
  alignas(64) std::atomic<std::uint32_t> completed_{0};
  std::atomic<bool> stop_{false};
  std::vector<std::thread> workers_;
};

// run(tasks, fn) on `pool`, or, without one (a world of one thread), every task in order on the
// calling thread (as thread 0).
template <class Fn>
void run_tasks(WorkerPool* pool, std::uint32_t tasks, Fn& fn) {
  if (pool != nullptr) return pool->run(tasks, fn);
  WorkerPool::run_inline(tasks, fn);
}

}  // namespace throng
