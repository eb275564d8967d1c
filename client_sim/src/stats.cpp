#include "throng/client_sim/stats.h"

#include <algorithm>
#include <cmath>

namespace throng::client_sim {

double percentile_sorted(std::span<const double> sorted, double p) {
  if (sorted.empty()) return 0.0;
  const double clamped = std::clamp(p, 0.0, 100.0);
  const auto n = static_cast<double>(sorted.size());
  // rank = ceil(p/100 * n), at least 1. The small epsilon keeps 0.9 * 100 = 90.00000000000001 at 90.
  auto rank = static_cast<std::size_t>(std::ceil(clamped / 100.0 * n - 1e-9));
  rank = std::clamp<std::size_t>(rank, 1, sorted.size());
  return sorted[rank - 1];
}

Summary summarize(std::span<const double> values) {
  Summary s;
  if (values.empty()) return s;
  std::vector<double> sorted(values.begin(), values.end());
  std::sort(sorted.begin(), sorted.end());
  s.count = sorted.size();
  double sum = 0;
  for (double v : sorted) sum += v;
  s.mean = sum / static_cast<double>(sorted.size());
  s.p50 = percentile_sorted(sorted, 50);
  s.p90 = percentile_sorted(sorted, 90);
  s.p99 = percentile_sorted(sorted, 99);
  s.max = sorted.back();
  return s;
}

}  // namespace throng::client_sim
