// The three Prometheus metric types as the tick thread sees them: plain objects whose updates are
// one or two relaxed atomic operations — no lock, no allocation — so updating them every tick costs
// nothing measurable while the admin thread renders them concurrently.
//
// They are created only by MetricsRegistry, which owns them at a stable address for its lifetime;
// callers keep the returned reference.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace throng::admin {

enum class MetricType { counter, gauge, histogram };

// A monotonically increasing count. Integer, because everything Throng counts (ticks, commands,
// rejections, bytes) is a whole number and integer atomics are exact and cheapest.
class Counter {
 public:
  Counter() = default;
  Counter(const Counter&) = delete;
  Counter& operator=(const Counter&) = delete;

  void inc(std::uint64_t n = 1) noexcept { value_.fetch_add(n, std::memory_order_relaxed); }
  std::uint64_t value() const noexcept { return value_.load(std::memory_order_relaxed); }

 private:
  std::atomic<std::uint64_t> value_{0};
};

// A value that goes up and down (connected clients, bodies, last tick duration).
class Gauge {
 public:
  Gauge() = default;
  Gauge(const Gauge&) = delete;
  Gauge& operator=(const Gauge&) = delete;

  void set(double v) noexcept { value_.store(v, std::memory_order_relaxed); }
  void add(double d) noexcept { value_.fetch_add(d, std::memory_order_relaxed); }
  void inc() noexcept { add(1.0); }
  void dec() noexcept { add(-1.0); }
  double value() const noexcept { return value_.load(std::memory_order_relaxed); }

 private:
  std::atomic<double> value_{0.0};
};

// A distribution over fixed upper bounds chosen at registration. Observations count into one
// non-cumulative slot each; render() accumulates, so `_count` always equals the `+Inf` bucket even
// while observations race with a scrape.
class Histogram {
 public:
  // `bounds` must be finite and strictly increasing (validated by the registry); +Inf is implicit.
  explicit Histogram(std::vector<double> bounds);
  Histogram(const Histogram&) = delete;
  Histogram& operator=(const Histogram&) = delete;

  // Bucket `le` is inclusive (v <= bound), as Prometheus defines it. NaN lands in +Inf only.
  void observe(double v) noexcept;

  std::span<const double> bounds() const noexcept { return bounds_; }
  // Non-cumulative count of slot i; i == bounds().size() is the overflow (+Inf only) slot.
  std::uint64_t slot_count(std::size_t i) const noexcept { return slots_[i].load(std::memory_order_relaxed); }
  double sum() const noexcept { return sum_.load(std::memory_order_relaxed); }

 private:
  std::vector<double> bounds_;
  std::unique_ptr<std::atomic<std::uint64_t>[]> slots_;  // bounds_.size() + 1 slots
  std::atomic<double> sum_{0.0};
};

// Bucket helpers for registration: `count` bounds start, start+width, ... / start, start*factor, ...
std::vector<double> linear_buckets(double start, double width, std::size_t count);
std::vector<double> exponential_buckets(double start, double factor, std::size_t count);

}  // namespace throng::admin
