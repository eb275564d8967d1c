#include "throng/server/keyframe_saver.h"

#include <chrono>
#include <stdexcept>

#include "throng/match/match.h"

namespace throng::server {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
}  // namespace

KeyframeSaver::KeyframeSaver(bool with_snapshot_baselines)
    : with_snapshot_baselines_(with_snapshot_baselines), thread_([this] { run(); }) {}

KeyframeSaver::~KeyframeSaver() {
  {
    std::unique_lock lock(mutex_);
    cv_.wait(lock, [this] { return !requested_ || done_; });  // never tear down mid-save
    stopping_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

void KeyframeSaver::start(const match::Match& match, std::uint64_t tick) {
  if (pending_) throw std::logic_error("KeyframeSaver::start: the previous keyframe was not finished");
  {
    std::lock_guard lock(mutex_);
    match_ = &match;
    tick_ = tick;
    requested_ = true;
    done_ = false;
    error_ = nullptr;
  }
  pending_ = true;
  cv_.notify_all();
}

bool KeyframeSaver::finish(Finished& out) {
  if (!pending_) return false;
  const auto t0 = Clock::now();
  std::unique_lock lock(mutex_);
  cv_.wait(lock, [this] { return done_; });
  pending_ = false;
  requested_ = false;
  match_ = nullptr;
  if (error_) std::rethrow_exception(error_);
  out.tick = tick_;
  out.bytes = &buffer_;
  out.save_seconds = save_seconds_;
  out.waited_seconds = seconds_since(t0);
  return true;
}

void KeyframeSaver::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    cv_.wait(lock, [this] { return stopping_ || (requested_ && !done_); });
    if (stopping_) return;
    const match::Match* m = match_;
    lock.unlock();  // the save runs unlocked: finish() and the destructor wait on done_
    const auto t0 = Clock::now();
    std::exception_ptr err;
    try {
      m->save_checkpoint(buffer_, match::SaveOptions{.snapshot_baselines = with_snapshot_baselines_});
    } catch (...) {
      err = std::current_exception();
    }
    const double took = seconds_since(t0);
    lock.lock();
    save_seconds_ = took;
    error_ = err;
    done_ = true;
    cv_.notify_all();
  }
}

}  // namespace throng::server
