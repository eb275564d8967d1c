#include "solver/pair_schedule.h"

#include <algorithm>

#include "solver/pair_schedule_build.h"

namespace throng::detail {

void build_pair_schedule(const SolverBodies& bodies, const std::vector<SolverPair>& pairs, double conflict_limit,
                         PairSchedule& s, WorkerPool* pool) {
  build_pair_schedule_from(bodies, SolverPairSource{pairs}, conflict_limit, s, pool);
}

std::uint32_t PairSchedule::choose_bands(float calm) {
  const std::size_t nb = band_count();
  band_busy_before.resize(nb + 1);
  band_swept.resize(nb);
  band_busy_before[0] = 0;
  for (std::size_t c = 0; c < nb; ++c) band_busy_before[c + 1] = band_busy_before[c] + (band_activity[c] >= calm ? 1u : 0u);
  std::uint32_t skipped = 0;
  for (std::size_t c = 0; c < nb; ++c) {
    band_swept[c] = band_busy_before[band_wake_hi[c] + 1] > band_busy_before[band_wake_lo[c]] ? 1 : 0;
    if (!band_swept[c]) {
      band_activity[c] = 0.0f;
      ++skipped;
    }
  }
  return skipped;
}

void write_back_pair_schedule(const PairSchedule& s, std::vector<SolverPair>& pairs) {
  for (std::size_t f = 0; f < s.fast_size(); ++f) {
    if (s.src[f] != PairSchedule::kNoPair) pairs[s.src[f]].lambda = static_cast<double>(s.lambda[f]);
  }
}

}  // namespace throng::detail
