// The three Prometheus metric types as the tick thread sees them: handles onto prometheus-cpp
// metrics that the registry owns. Updates never allocate. Counters and gauges are a
// compare-and-swap on an atomic double; a histogram observation takes that histogram's own mutex
// (prometheus-cpp's), held for two additions, which a scrape holds only while it copies that one
// histogram: at worst a tick waits for one histogram's copy.
//
// Only MetricsRegistry makes them, at a stable address for its lifetime; callers keep the
// returned reference. prometheus-cpp stays out of this header (its types are only declared), so
// code that updates metrics does not compile against it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace prometheus {
class Counter;
class Gauge;
class Histogram;
}  // namespace prometheus

namespace throng::admin {

// A monotonically increasing count. prometheus-cpp keeps it as a double, which counts whole
// numbers exactly up to 2^53: far beyond any tick, command or byte count of a match.
class Counter {
 public:
  explicit Counter(prometheus::Counter& metric) noexcept : metric_(&metric) {}
  Counter(const Counter&) = delete;
  Counter& operator=(const Counter&) = delete;

  void inc(std::uint64_t n = 1) noexcept;
  // Raises the count to a total kept elsewhere (a lower total changes nothing): for counters that
  // mirror another component's own count. Not atomic against a concurrent inc on this counter.
  void raise_to(std::uint64_t total) noexcept;
  std::uint64_t value() const noexcept;

 private:
  prometheus::Counter* metric_;
};

// A value that goes up and down (connected clients, bodies, last tick duration).
class Gauge {
 public:
  explicit Gauge(prometheus::Gauge& metric) noexcept : metric_(&metric) {}
  Gauge(const Gauge&) = delete;
  Gauge& operator=(const Gauge&) = delete;

  void set(double v) noexcept;
  void add(double d) noexcept;
  void inc() noexcept { add(1.0); }
  void dec() noexcept { add(-1.0); }
  double value() const noexcept;

 private:
  prometheus::Gauge* metric_;
};

// A distribution over fixed upper bounds chosen at registration; +Inf is implicit.
class Histogram {
 public:
  explicit Histogram(prometheus::Histogram& metric) noexcept : metric_(&metric) {}
  Histogram(const Histogram&) = delete;
  Histogram& operator=(const Histogram&) = delete;

  // Bucket `le` is inclusive (v <= bound), as Prometheus defines it. NaN counts in +Inf only.
  void observe(double v) noexcept;

 private:
  prometheus::Histogram* metric_;
};

// Bucket helpers for registration: `count` bounds start, start+width, ... / start, start*factor, ...
std::vector<double> linear_buckets(double start, double width, std::size_t count);
std::vector<double> exponential_buckets(double start, double factor, std::size_t count);

}  // namespace throng::admin
