#pragma once
// Tick-duration percentiles without storing every tick: a log-spaced histogram (2% wide buckets
// from 1 µs to 100 s), so a week-long match costs the same memory as a minute and p99 is exact to
// within 2%. The per-second window for ServerStats uses the same type, reset each second.
#include <array>
#include <cstdint>

namespace throng::server {

class DurationStats {
 public:
  void add(double seconds);
  void reset() { *this = DurationStats{}; }
  std::uint64_t count() const { return count_; }
  double max() const { return max_; }
  double mean() const { return count_ ? sum_ / static_cast<double>(count_) : 0.0; }
  // q in [0, 1]; the upper edge of the bucket holding the q-quantile (never below the true value
  // by more than one bucket). 0 with no samples.
  double quantile(double q) const;

 private:
  static constexpr int kBuckets = 1200;  // 1.02^1200 ≈ 2e10 : 1 µs .. ~20,000 s
  std::array<std::uint32_t, kBuckets> buckets_{};
  std::uint64_t count_ = 0;
  double sum_ = 0.0;
  double max_ = 0.0;
};

}  // namespace throng::server
