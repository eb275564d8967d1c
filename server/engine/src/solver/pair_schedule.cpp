#include "solver/pair_schedule.h"

#include <algorithm>

namespace throng::detail {

void build_pair_schedule(const SolverBodies& bodies, const std::vector<SolverPair>& pairs, double conflict_limit,
                         PairSchedule& s) {
  const std::size_t np = pairs.size();
  s.next_level.assign(bodies.size(), 0);
  s.pair_level.resize(np);
  std::uint32_t level_count = 0;
  std::uint32_t fast_total = 0;
  for (std::size_t k = 0; k < np; ++k) {
    const SolverPair& p = pairs[k];
    const std::uint32_t lv = std::max(s.next_level[p.a], s.next_level[p.b]);
    s.next_level[p.a] = s.next_level[p.b] = lv + 1;
    s.pair_level[k] = lv;
    level_count = std::max(level_count, lv + 1);
  }
  s.fast_count.assign(level_count + 1, 0);
  s.slow_count.assign(level_count + 1, 0);
  auto is_fast = [&](const SolverPair& p) {
    return p.target >= 0.0 && (bodies.plane_count[p.a] | bodies.plane_count[p.b]) == 0;
  };
  for (std::size_t k = 0; k < np; ++k) {
    if (is_fast(pairs[k])) {
      ++s.fast_count[s.pair_level[k]];
      ++fast_total;
    } else {
      ++s.slow_count[s.pair_level[k]];
    }
  }
  // Counting sort by level (stable: within a level, pairs keep the broadphase order).
  s.levels.resize(level_count);
  std::uint32_t fast_at = 0, slow_at = 0;
  for (std::uint32_t lv = 0; lv < level_count; ++lv) {
    s.levels[lv] = {fast_at, fast_at + s.fast_count[lv], slow_at, slow_at + s.slow_count[lv]};
    s.fast_count[lv] = fast_at;  // now the next free slot of the level
    s.slow_count[lv] = slow_at;
    fast_at = s.levels[lv].fast_end;
    slow_at = s.levels[lv].slow_end;
  }
  s.a.resize(fast_total); s.b.resize(fast_total); s.target.resize(fast_total);
  s.share_now.resize(fast_total); s.share_conflict.resize(fast_total); s.lambda.resize(fast_total);
  s.inv_r_min.resize(fast_total); s.resolved.resize(fast_total); s.src.resize(fast_total);
  s.slow.resize(np - fast_total);
  const double* r = bodies.r.data();
  for (std::size_t k = 0; k < np; ++k) {
    const SolverPair& p = pairs[k];
    const std::uint32_t lv = s.pair_level[k];
    if (!is_fast(p)) {
      s.slow[s.slow_count[lv]++] = static_cast<std::uint32_t>(k);
      continue;
    }
    const std::uint32_t f = s.fast_count[lv]++;
    s.a[f] = p.a;
    s.b[f] = p.b;
    s.target[f] = p.target;
    // The same share the general projection would pick (contact_solver.cpp).
    const double conflict =
        conflict_limit > 0.0 ? std::clamp(p.share_a, conflict_limit, 1.0 - conflict_limit) : p.share_a;
    s.share_conflict[f] = conflict;
    s.share_now[f] = p.resolved_once != 0 ? conflict : p.share_a;
    s.lambda[f] = p.lambda;
    s.inv_r_min[f] = 1.0 / std::min(r[p.a], r[p.b]);
    s.resolved[f] = static_cast<std::uint8_t>(p.resolved_once != 0);
    s.src[f] = static_cast<std::uint32_t>(k);
  }
}

void write_back_pair_schedule(const PairSchedule& s, std::vector<SolverPair>& pairs) {
  for (std::size_t f = 0; f < s.fast_size(); ++f) {
    SolverPair& p = pairs[s.src[f]];
    p.lambda = s.lambda[f];
    p.resolved_once = s.resolved[f];
  }
}

}  // namespace throng::detail
