// The crowd solve on several threads (WorldSettings::threads): the blocks of one phase of the
// schedule share no body, so sharing them among threads gives the same bits as sweeping them in
// order, for any number of threads (solver/pair_schedule.h, PairSchedule::block_band).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <cstring>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include "solver/contact_solver.h"
#include "solver/pair_schedule.h"
#include "solver/solver_data.h"
#include "throng/core/worker_pool.h"

namespace throng::detail {
namespace {

TEST(WorkerPool, RunsEveryTaskOnceAndNamesItsThread) {
  WorkerPool pool(3);
  ASSERT_EQ(pool.threads(), 3u);
  for (std::uint32_t tasks : {0u, 1u, 2u, 7u, 1000u}) {
    for (int round = 0; round < 50; ++round) {
      std::vector<std::atomic<int>> runs(tasks);
      std::atomic<int> bad_thread{0};
      auto fn = [&](std::uint32_t t, unsigned thread) {
        runs[t].fetch_add(1);
        if (thread >= 3) bad_thread.fetch_add(1);
      };
      pool.run(tasks, fn);
      for (std::uint32_t t = 0; t < tasks; ++t) ASSERT_EQ(runs[t].load(), 1) << "task " << t << " of " << tasks;
      ASSERT_EQ(bad_thread.load(), 0);
    }
  }
}

// Runs of few tasks and of many, back to back: a thread still looking at a finished run of few
// tasks when the next run of many is being announced must not take one of the new run's tasks
// early (it then ran twice, and the caller's count of completed tasks could step past its run's
// and wait for ever; found as a hang of the test above).
TEST(WorkerPool, RunsOfFewAndManyTasksBackToBackRunEachTaskOnce) {
  // More threads than this machine's cores: a thread preempted between its two reads widens the
  // window the race needs.
  WorkerPool pool(8);
  std::vector<std::atomic<int>> runs(64);
  auto fn = [&](std::uint32_t t) { runs[t].fetch_add(1, std::memory_order_relaxed); };
  for (int round = 0; round < 100000; ++round) {
    const std::uint32_t tasks = round % 2 == 0 ? 2u : 64u;
    for (std::uint32_t t = 0; t < tasks; ++t) runs[t].store(0, std::memory_order_relaxed);
    pool.run(tasks, fn);
    for (std::uint32_t t = 0; t < tasks; ++t) ASSERT_EQ(runs[t].load(), 1) << "round " << round << " task " << t;
  }
}

TEST(WorkerPool, RejectsThreadCountsOutsideItsRange) {
  EXPECT_THROW(WorkerPool(0), std::invalid_argument);
  EXPECT_THROW(WorkerPool(WorkerPool::kMaxThreads + 1), std::invalid_argument);
  WorkerPool one(1);
  int sum = 0;
  auto fn = [&](std::uint32_t t) { sum += static_cast<int>(t); };
  one.run(5, fn);
  EXPECT_EQ(sum, 10);
}

// A jittered lattice of small bodies with some large ones among them (their pairs come after the
// small ones', as the broadphase lists a coarser level's pairs): pairs in scan order, unequal
// shares, warm pushes. Enough pairs for many bands, so the schedule has several blocks per phase.
struct Crowd {
  SolverBodies bodies;
  std::vector<SolverPair> pairs;
};

Crowd make_crowd(std::uint32_t cols, std::uint32_t rows, std::uint32_t seed) {
  Crowd c;
  const std::uint32_t n = cols * rows;
  c.bodies.resize(n);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.08, 0.08), share(0.1, 0.9), warm(0.0, 0.05);
  for (std::uint32_t i = 0; i < n; ++i) {
    const bool big = i % 97 == 13;
    c.bodies.x[i] = 0.9 * (i % cols) + jitter(rng);
    c.bodies.y[i] = 0.9 * (i / cols) + jitter(rng);
    c.bodies.r[i] = big ? 0.8 : 0.5;
    c.bodies.z[i] = 0.9;
    c.bodies.hh[i] = 0.4;
    c.bodies.grounded[i] = 1;
    c.bodies.plane_begin[i] = 0;
    c.bodies.plane_count[i] = 0;
    c.bodies.id[i] = i + 1;
  }
  auto add = [&](std::uint32_t a, std::uint32_t b) {
    SolverPair p{};
    p.a = a;
    p.b = b;
    p.target = c.bodies.r[a] + c.bodies.r[b];
    p.share_a = share(rng);
    p.lambda = warm(rng);
    c.pairs.push_back(p);
  };
  for (std::uint32_t i = 0; i < n; ++i) {
    if (i % cols + 1 < cols) add(i, i + 1);
    if (i + cols < n) add(i, i + cols);
    if (i % cols + 1 < cols && i + cols < n) add(i, i + cols + 1);
  }
  // The large bodies' pairs with the bodies two rows away, listed last.
  for (std::uint32_t i = 13; i + 2 * cols < n; i += 97) add(i, i + 2 * cols);
  return c;
}

struct Solved {
  std::vector<float> u, lambda;
  std::vector<double> slow_lambda;
  SolveResult result;
  std::size_t phases = 0, blocks = 0;
};

Solved solve_with(const Crowd& crowd, unsigned threads) {
  SolverBodies b = crowd.bodies;
  std::vector<SolverPair> p = crowd.pairs;
  b.displaced = true;
  std::fill(b.u.begin(), b.u.end(), 0.0f);
  std::unique_ptr<WorkerPool> pool = threads > 1 ? std::make_unique<WorkerPool>(threads) : nullptr;
  PairSchedule s;
  build_pair_schedule(b, p, 0.25, s, pool.get());
  const std::vector<SolverPlane> no_planes;
  apply_warm_start(b, p, no_planes, s, 0.25, pool.get());
  Solved out;
  out.result = solve_contacts(b, p, no_planes, 8, 0, 0.0, 0.25, s, true, pool.get());
  out.u = b.u;
  out.lambda = s.lambda;
  for (const std::uint32_t k : s.slow) out.slow_lambda.push_back(p[k].lambda);
  out.phases = s.phase_count();
  out.blocks = s.block_count();
  return out;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(ThreadedSolve, SameBitsForOneTwoAndFourThreads) {
  const Crowd crowd = make_crowd(180, 160, 7);
  const Solved one = solve_with(crowd, 1);
  // Several blocks share a phase: the threads really sweep side by side.
  ASSERT_GE(one.blocks, 2 * one.phases) << one.blocks << " blocks in " << one.phases << " phases";
  // Something to get wrong: the sweeps moved the crowd.
  ASSERT_GT(*std::max_element(one.u.begin(), one.u.end()), 0.01f);
  for (unsigned threads : {2u, 4u}) {
    for (int repeat = 0; repeat < 3; ++repeat) {
      const Solved many = solve_with(crowd, threads);
      EXPECT_TRUE(same_bits(one.u, many.u)) << threads << " threads";
      EXPECT_TRUE(same_bits(one.lambda, many.lambda)) << threads << " threads";
      EXPECT_EQ(one.slow_lambda, many.slow_lambda) << threads << " threads";
      EXPECT_EQ(one.result.max_pen_over_radius, many.result.max_pen_over_radius);
      EXPECT_EQ(one.result.iterations_used, many.result.iterations_used);
      EXPECT_EQ(one.result.band_sweeps_skipped, many.result.band_sweeps_skipped);
    }
  }
}

// The colouring: blocks of one phase touch disjoint bodies, every band is in exactly one block and
// every block in exactly one phase.
TEST(ThreadedSolve, BlocksOfOnePhaseShareNoBody) {
  Crowd crowd = make_crowd(180, 160, 11);
  PairSchedule s;
  build_pair_schedule(crowd.bodies, crowd.pairs, 0.25, s);
  ASSERT_GT(s.phase_count(), 1u);
  ASSERT_EQ(s.block_band.front(), 0u);
  ASSERT_EQ(s.block_band.back(), s.band_count());
  for (std::size_t k = 0; k + 1 < s.block_band.size(); ++k) ASSERT_LT(s.block_band[k], s.block_band[k + 1]);
  std::vector<int> seen(s.block_count(), 0);
  for (const std::uint32_t k : s.phase_block) ++seen[k];
  for (const int v : seen) ASSERT_EQ(v, 1);
  // The bodies of each block, from its pairs (fast and slow).
  std::vector<std::set<std::uint32_t>> bodies(s.block_count());
  for (std::size_t k = 0; k < s.block_count(); ++k) {
    for (std::uint32_t f = s.block_fast_begin(k); f < s.block_fast_end(k); ++f) {
      if (s.src[f] == PairSchedule::kNoPair) continue;
      bodies[k].insert(s.a[f]);
      bodies[k].insert(s.b[f]);
    }
    const std::uint32_t l0 = s.band_level[s.block_band[k]], l1 = s.band_level[s.block_band[k + 1]];
    for (std::uint32_t q = s.levels[l0].slow_begin; q < s.levels[l1 - 1].slow_end; ++q) {
      bodies[k].insert(crowd.pairs[s.slow[q]].a);
      bodies[k].insert(crowd.pairs[s.slow[q]].b);
    }
  }
  std::size_t shared_across_phases = 0;
  for (std::size_t p = 0; p < s.phase_count(); ++p) {
    for (std::uint32_t i = s.phase_begin[p]; i < s.phase_begin[p + 1]; ++i) {
      for (std::uint32_t j = i + 1; j < s.phase_begin[p + 1]; ++j) {
        for (const std::uint32_t body : bodies[s.phase_block[i]]) {
          ASSERT_EQ(bodies[s.phase_block[j]].count(body), 0u)
              << "body " << body << " in blocks " << s.phase_block[i] << " and " << s.phase_block[j] << " of phase " << p;
        }
      }
    }
  }
  // Neighbouring blocks do share bodies (so the test above could fail): they are in other phases.
  for (const std::uint32_t body : bodies[0]) shared_across_phases += bodies[1].count(body);
  EXPECT_GT(shared_across_phases, 0u);
}

}  // namespace
}  // namespace throng::detail
