#pragma once
// throng-bench sweep: speed against error on the crush scene.
//   1. iterations K in {1, 2, 3, 4, 6, 8, 12, 16} at N = 20,000 — what each extra iteration buys;
//   2. N in {1k, 2k, 5k, 10k, 20k, 50k, 100k} at the default K — is the cost per agent flat (O(N))?
//   3. one_cell against crush at the same N and K — the broadphase worst case, as a cost ratio.
// Writes a table to stdout, sweep.json and sweep.svg to the output folder, progress to stderr.
#include <cstdint>
#include <string>
#include <vector>

namespace throng::bench {

struct SweepPlan {
  std::vector<std::uint32_t> iterations;  // K values
  std::uint64_t k_agents = 20'000;
  std::vector<std::uint64_t> agents;      // N values
  std::uint64_t ticks = 300;
  std::uint64_t one_cell_agents = 20'000;  // must be one of `agents` (the uniform reference)
  std::uint64_t residual_from = 61;        // the worst tick is taken from this tick on
};

// quick: a CI smoke test (seconds, not minutes) with the same structure.
SweepPlan sweep_plan(bool quick);

// Returns the process exit code.
int run_sweep(const SweepPlan& plan, const std::string& out_dir);

}  // namespace throng::bench
