#pragma once
// Helpers for the loopback transport tests: a thread-safe inbox the DDS listener threads push
// into and the test waits on (condition variable, bounded), and the options of a test participant.
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "throng/protocol/dds_transport.h"
#include "throng/protocol/messages.h"

namespace throng::protocol::test {

// Every bounded wait in these tests; far below ctest's 120 s per-test timeout.
inline constexpr std::chrono::seconds kWait{10};

// Each test uses its own domain (110..139) so parallel ctest runs never see each other.
inline TransportOptions loopback(int domain_id, const std::string& name) {
  TransportOptions o;
  o.domain_id = domain_id;
  o.loopback_only = true;
  o.participant_name = name;
  return o;
}

// Declare an inbox before the transport whose handlers push into it: locals are destroyed in
// reverse order, and a transport's listener threads may deliver until its destructor returns.
template <class T>
class Inbox {
 public:
  void push(T value) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      items_.push_back(std::move(value));
    }
    arrived_.notify_all();
  }

  // Waits until at least n items arrived; false on timeout.
  bool wait_for_count(std::size_t n, std::chrono::milliseconds timeout = kWait) {
    std::unique_lock<std::mutex> lock(mutex_);
    return arrived_.wait_for(lock, timeout, [&] { return items_.size() >= n; });
  }

  // Waits until pred(items) holds; false on timeout.
  bool wait_until(const std::function<bool(const std::vector<T>&)>& pred,
                  std::chrono::milliseconds timeout = kWait) {
    std::unique_lock<std::mutex> lock(mutex_);
    return arrived_.wait_for(lock, timeout, [&] { return pred(items_); });
  }

  std::vector<T> items() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return items_;
  }

  std::size_t size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return items_.size();
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::vector<T> items_;
};

// Sends, then waits up to `period` for the result, and again, until `wait_done` says it arrived or
// the timeout passes: best-effort topics drop the samples written before the reader's side of
// discovery has finished, so a single send is not enough.
inline bool send_until(const std::function<void()>& send,
                       const std::function<bool(std::chrono::milliseconds)>& wait_done,
                       std::chrono::milliseconds period = std::chrono::milliseconds(50),
                       std::chrono::milliseconds timeout = kWait) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    send();
    if (wait_done(period)) return true;
  }
  return false;
}

}  // namespace throng::protocol::test
