#include "throng/admin/metric_types.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace throng::admin {

Histogram::Histogram(std::vector<double> bounds)
    : bounds_(std::move(bounds)), slots_(std::make_unique<std::atomic<std::uint64_t>[]>(bounds_.size() + 1)) {}

void Histogram::observe(double v) noexcept {
  // First bound >= v. NaN compares false with everything, so it falls through to the +Inf slot
  // (as in the Go client) instead of landing in the first bucket.
  const auto it = std::lower_bound(bounds_.begin(), bounds_.end(), v);
  const std::size_t slot = std::isnan(v) ? bounds_.size() : static_cast<std::size_t>(it - bounds_.begin());
  slots_[slot].fetch_add(1, std::memory_order_relaxed);
  sum_.fetch_add(v, std::memory_order_relaxed);
}

std::vector<double> linear_buckets(double start, double width, std::size_t count) {
  if (!(width > 0.0)) throw std::invalid_argument("linear_buckets: width must be > 0");
  std::vector<double> out;
  out.reserve(count);
  for (std::size_t i = 0; i < count; ++i) out.push_back(start + width * static_cast<double>(i));
  return out;
}

std::vector<double> exponential_buckets(double start, double factor, std::size_t count) {
  if (!(start > 0.0)) throw std::invalid_argument("exponential_buckets: start must be > 0");
  if (!(factor > 1.0)) throw std::invalid_argument("exponential_buckets: factor must be > 1");
  std::vector<double> out;
  out.reserve(count);
  for (double b = start; out.size() < count; b *= factor) out.push_back(b);
  return out;
}

}  // namespace throng::admin
