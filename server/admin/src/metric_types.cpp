#include "throng/admin/metric_types.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <prometheus/counter.h>
#include <prometheus/gauge.h>
#include <prometheus/histogram.h>

namespace throng::admin {

void Counter::inc(std::uint64_t n) noexcept { metric_->Increment(static_cast<double>(n)); }
std::uint64_t Counter::value() const noexcept { return static_cast<std::uint64_t>(metric_->Value()); }
void Counter::raise_to(std::uint64_t total) noexcept {
  if (const std::uint64_t now = value(); total > now) inc(total - now);
}

void Gauge::set(double v) noexcept { metric_->Set(v); }
void Gauge::add(double d) noexcept { metric_->Increment(d); }
double Gauge::value() const noexcept { return metric_->Value(); }

void Histogram::observe(double v) noexcept {
  // prometheus-cpp finds the bucket with lower_bound, where NaN compares false with every bound and
  // so lands in the first bucket. Counted as +Inf it lands in +Inf only, as the Go client puts it;
  // the sum then reads +Inf instead of NaN, spoilt either way.
  metric_->Observe(std::isnan(v) ? std::numeric_limits<double>::infinity() : v);
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
