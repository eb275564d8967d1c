#include "worker_pool.h"

namespace throng::match {

WorkerPool::WorkerPool(unsigned threads) {
  for (unsigned w = 1; w < threads; ++w) threads_.emplace_back([this, w] { work(w); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  start_cv_.notify_all();
  for (auto& t : threads_) t.join();
}

void WorkerPool::drain(unsigned worker) {
  for (std::size_t i; (i = next_.fetch_add(1, std::memory_order_relaxed)) < count_;) call_(ctx_, worker, i);
}

void WorkerPool::run(std::size_t n, Call call, void* ctx) {
  if (threads_.empty() || n <= 1) {
    for (std::size_t i = 0; i < n; ++i) call(ctx, 0, i);
    return;
  }
  {
    std::lock_guard lock(mutex_);
    call_ = call;
    ctx_ = ctx;
    count_ = n;
    next_.store(0, std::memory_order_relaxed);
    busy_ = static_cast<unsigned>(threads_.size());
    ++generation_;
  }
  start_cv_.notify_all();
  drain(0);
  std::unique_lock lock(mutex_);
  done_cv_.wait(lock, [this] { return busy_ == 0; });
}

void WorkerPool::work(unsigned worker) {
  std::uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      start_cv_.wait(lock, [&] { return stopping_ || generation_ != seen; });
      if (stopping_) return;
      seen = generation_;
    }
    drain(worker);
    {
      std::lock_guard lock(mutex_);
      --busy_;
    }
    done_cv_.notify_one();
  }
}

}  // namespace throng::match
