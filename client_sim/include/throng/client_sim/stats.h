#pragma once
// Percentiles of measured samples (latencies, inter-arrival times, join times).
//
// Percentiles use the nearest-rank definition: the p-th percentile of n sorted samples is the
// sample at rank ceil(p/100 * n) (1-based), i.e. the smallest sample such that at least p% of the
// samples are <= it. It is always one of the measured values (no interpolation), p0 is the
// minimum and p100 the maximum. An empty set summarizes to all zeros with count 0.
#include <cstddef>
#include <span>
#include <vector>

namespace throng::client_sim {

struct Summary {
  std::size_t count = 0;
  double mean = 0, p50 = 0, p90 = 0, p99 = 0, max = 0;
};

// p in [0, 100]; sorted must be ascending and non-empty (else 0 is returned).
double percentile_sorted(std::span<const double> sorted, double p);

// Copies, sorts and summarizes.
Summary summarize(std::span<const double> values);

// A growing set of samples with a cheap append, summarized on demand.
class Samples {
 public:
  void add(double v) { values_.push_back(v); }
  void append(const Samples& other) { values_.insert(values_.end(), other.values_.begin(), other.values_.end()); }
  void clear() { values_.clear(); }
  std::size_t size() const { return values_.size(); }
  bool empty() const { return values_.empty(); }
  std::span<const double> values() const { return values_; }
  Summary summary() const { return summarize(values_); }

 private:
  std::vector<double> values_;
};

}  // namespace throng::client_sim
