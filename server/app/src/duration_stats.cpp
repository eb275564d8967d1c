#include "throng/server/duration_stats.h"

#include <algorithm>
#include <cmath>

namespace throng::server {

namespace {
constexpr double kMin = 1e-6;
constexpr double kGrowth = 1.02;
}  // namespace

void DurationStats::add(double seconds) {
  if (!(seconds >= 0.0)) return;  // NaN or negative: a clock bug, never a real duration
  ++count_;
  sum_ += seconds;
  max_ = std::max(max_, seconds);
  int b = 0;
  if (seconds > kMin) b = static_cast<int>(std::ceil(std::log(seconds / kMin) / std::log(kGrowth)));
  b = std::clamp(b, 0, kBuckets - 1);
  ++buckets_[static_cast<std::size_t>(b)];
}

double DurationStats::quantile(double q) const {
  if (count_ == 0) return 0.0;
  const auto rank = static_cast<std::uint64_t>(std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(count_)));
  std::uint64_t seen = 0;
  for (int b = 0; b < kBuckets; ++b) {
    seen += buckets_[static_cast<std::size_t>(b)];
    if (seen >= std::max<std::uint64_t>(rank, 1)) return std::min(max_, kMin * std::pow(kGrowth, b));
  }
  return max_;
}

}  // namespace throng::server
