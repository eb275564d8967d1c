// A scheduled solve leaves out the bands of its schedule that nothing near has pushed in the last
// sweep (solver/pair_schedule.h, kCalmPushOverRadius). Two things must hold: a band is visited
// whenever a band sharing a body with it pushed (the wake ranges cover every shared body), and a
// band left out had nothing to do (leaving out a resting crowd changes no bit).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <vector>

#include "solver/contact_solver.h"
#include "solver/pair_schedule.h"
#include "solver/solver_data.h"

namespace throng::detail {
namespace {

void set_body(SolverBodies& b, std::uint32_t i, double x, double y, double r) {
  b.x[i] = x;
  b.y[i] = y;
  b.r[i] = r;
  b.z[i] = 0.5;
  b.hh[i] = 0.0;
  b.grounded[i] = 1;
  b.plane_begin[i] = 0;
  b.plane_count[i] = 0;
  b.id[i] = i + 1;
}

SolverPair grounded_pair(const SolverBodies& b, std::uint32_t i, std::uint32_t j) {
  SolverPair p{};
  p.a = i;
  p.b = j;
  p.target = b.r[i] + b.r[j];
  p.share_a = 0.5;
  return p;
}

// Right and up neighbours of a `cols`-wide lattice of bodies [first, first + count), in row-major
// (scan) order, as the broadphase lists a crowd's pairs.
void add_lattice_pairs(const SolverBodies& b, std::uint32_t first, std::uint32_t count, std::uint32_t cols,
                       std::vector<SolverPair>& pairs) {
  for (std::uint32_t k = 0; k < count; ++k) {
    if (k % cols + 1 < cols) pairs.push_back(grounded_pair(b, first + k, first + k + 1));
    if (k + cols < count) pairs.push_back(grounded_pair(b, first + k, first + k + cols));
  }
}

// A scheduled solve (conflict limit 0.25) of copies of the bodies and pairs, leaving out bands
// calmer than `calm` (0: none); `narrow_wake` shrinks every band's wake range to the band itself.
// Returns the displacements.
std::vector<float> scheduled_solve(const SolverBodies& bodies, const std::vector<SolverPair>& pairs,
                                   std::uint32_t sweeps, float calm, bool narrow_wake, SolveResult& result) {
  SolverBodies b = bodies;
  std::vector<SolverPair> p = pairs;
  b.displaced = true;
  std::fill(b.u.begin(), b.u.end(), 0.0f);
  PairSchedule s;
  build_pair_schedule(b, p, 0.25, s);
  s.calm_push_over_radius = calm;
  if (narrow_wake) {
    for (std::size_t c = 0; c < s.band_count(); ++c) s.band_wake_lo[c] = s.band_wake_hi[c] = static_cast<std::uint32_t>(c);
  }
  const std::vector<SolverPlane> no_planes;
  result = solve_contacts(b, p, no_planes, sweeps, 0, 0.0, 0.25, s, true);
  return b.u;
}

// Every pair of bands that share a body lies in each other's wake range, on random pair lists laid
// out as the grid lays them out: a crowd's pairs in scan order, then the pairs of five giants
// (the last bodies in solver order, on a coarser grid level) with bodies all over the crowd.
TEST(CalmBands, WakeRangesCoverEveryBandSharingABody) {
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const std::uint32_t n = 3000, giants = 5, crowd = n - giants;
    SolverBodies bodies;
    bodies.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) set_body(bodies, i, 0.7 * (i % 60), 0.7 * (i / 60), i < crowd ? 0.35 : 1.4);
    std::vector<SolverPair> pairs;
    const std::size_t count = 3 * kScheduleChunkPairs + rng() % kScheduleChunkPairs;
    for (std::size_t k = 0; k < count; ++k) {
      const std::uint32_t a = static_cast<std::uint32_t>(k * crowd / count);
      const std::uint32_t b = std::min<std::uint32_t>(crowd - 1, a + 1 + static_cast<std::uint32_t>(rng() % 70));
      if (a != b) pairs.push_back(grounded_pair(bodies, a, b));
    }
    const std::size_t giant_pairs = 200 + rng() % 3000;  // in 0-2 bands of their own
    for (std::size_t k = 0; k < giant_pairs; ++k) {
      pairs.push_back(grounded_pair(bodies, crowd + static_cast<std::uint32_t>(k % giants),
                                    static_cast<std::uint32_t>(rng() % crowd)));
    }
    PairSchedule s;
    build_pair_schedule(bodies, pairs, 0.0, s);
    const std::size_t nb = s.band_count();
    ASSERT_EQ(nb, (pairs.size() + kScheduleChunkPairs - 1) / kScheduleChunkPairs);
    std::vector<std::set<std::uint32_t>> bodies_of(nb);
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      bodies_of[k / kScheduleChunkPairs].insert(pairs[k].a);
      bodies_of[k / kScheduleChunkPairs].insert(pairs[k].b);
    }
    for (std::size_t c = 0; c < nb; ++c) {
      for (std::size_t d = 0; d < nb; ++d) {
        bool shared = false;
        for (const std::uint32_t x : bodies_of[c]) shared = shared || bodies_of[d].count(x) != 0;
        if (!shared) continue;
        EXPECT_LE(s.band_wake_lo[c], d) << "trial " << trial << " band " << c << " shares a body with " << d;
        EXPECT_GE(s.band_wake_hi[c], d) << "trial " << trial << " band " << c << " shares a body with " << d;
      }
    }
  }
}

// A jam followed (in pair order and in body order) by a large resting crowd whose pairs are all
// 1 cm apart: after the first sweeps the resting crowd's bands are left out, and the result is
// bit for bit the result of visiting every band in every sweep.
TEST(CalmBands, RestingCrowdIsLeftOutWithoutChangingABit) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const std::uint32_t jam = 1200, rest_side = 80, rest = rest_side * rest_side;
  SolverBodies bodies;
  bodies.resize(jam + rest);
  for (std::uint32_t i = 0; i < jam; ++i) set_body(bodies, i, 20.0 * unit(rng), 20.0 * unit(rng), 0.35);
  std::vector<SolverPair> pairs;
  for (std::uint32_t i = 0; i < jam; ++i) {
    for (std::uint32_t j = i + 1; j < jam; ++j) {
      const double dx = bodies.x[j] - bodies.x[i], dy = bodies.y[j] - bodies.y[i];
      if (dx * dx + dy * dy < 0.7 * 0.7) pairs.push_back(grounded_pair(bodies, i, j));
    }
  }
  const std::size_t jam_pairs = pairs.size();
  ASSERT_GT(jam_pairs, 500u);
  // The resting crowd: a square lattice 1,000 m away, neighbours 0.71 m apart (radius sum 0.70).
  for (std::uint32_t k = 0; k < rest; ++k) {
    set_body(bodies, jam + k, 1000.0 + 0.71 * (k % rest_side), 0.71 * (k / rest_side), 0.35);
  }
  add_lattice_pairs(bodies, jam, rest, rest_side, pairs);
  const std::uint32_t sweeps = 8;
  SolveResult all, skipping;
  const std::vector<float> u_all = scheduled_solve(bodies, pairs, sweeps, 0.0f, false, all);
  const std::vector<float> u_skipping = scheduled_solve(bodies, pairs, sweeps, kCalmPushOverRadius, false, skipping);

  const std::size_t bands = (pairs.size() + kScheduleChunkPairs - 1) / kScheduleChunkPairs;
  const std::size_t resting_bands = pairs.size() / kScheduleChunkPairs - (jam_pairs + kScheduleChunkPairs - 1) / kScheduleChunkPairs;
  ASSERT_GE(resting_bands, 3u);
  EXPECT_EQ(all.band_sweeps, bands * sweeps);
  EXPECT_EQ(all.band_sweeps_skipped, 0u);
  EXPECT_EQ(skipping.band_sweeps, bands * sweeps);
  // Every band that touches only resting bodies, in every sweep after the first kFullSweeps; the
  // band that holds both the jam's last pairs and the rest's first is visited while the jam pushes.
  EXPECT_GE(skipping.band_sweeps_skipped, (resting_bands - 1) * (sweeps - kFullSweeps));
  EXPECT_LE(skipping.band_sweeps_skipped, resting_bands * (sweeps - kFullSweeps));
  EXPECT_EQ(u_skipping, u_all);
  EXPECT_EQ(skipping.max_pen_over_radius, all.max_pen_over_radius);
  // The jam really was pushed apart.
  float moved = 0.0f;
  for (std::uint32_t i = 0; i < jam; ++i) moved = std::max(moved, std::fabs(u_all[2 * i]));
  EXPECT_GT(moved, 0.05f);
}

// The choice itself: a band is visited when any band in its wake range pushed by `calm` or more
// in its last sweep (including itself), and a band left out is recorded as having pushed nothing.
TEST(CalmBands, BandsNextToABusyBandAreVisited) {
  PairSchedule s;
  s.band_level = {0, 1, 2, 3, 4, 5, 6};  // six bands
  // Bands 0-4 share bodies with their neighbours; band 5 holds the pairs of a giant standing among
  // the bodies of bands 3 and 4.
  s.band_wake_lo = {0, 0, 1, 2, 3, 3};
  s.band_wake_hi = {1, 2, 3, 5, 5, 5};
  const float calm = 1e-3f;

  s.band_activity = {0.0f, 0.0f, 0.0f, 5e-3f, 0.0f, 0.0f};
  EXPECT_EQ(s.choose_bands(calm), 2u);
  EXPECT_EQ(s.band_swept, (std::vector<std::uint8_t>{0, 0, 1, 1, 1, 1}));
  EXPECT_EQ(s.band_activity, (std::vector<float>{0.0f, 0.0f, 0.0f, 5e-3f, 0.0f, 0.0f}));

  // Just below the threshold is calm, and a band left out is recorded as not having moved.
  s.band_activity = {0.0f, 0.9e-3f, 0.0f, 0.0f, 0.0f, 0.0f};
  EXPECT_EQ(s.choose_bands(calm), 6u);
  EXPECT_EQ(s.band_swept, (std::vector<std::uint8_t>(6, 0)));
  EXPECT_EQ(s.band_activity, (std::vector<float>(6, 0.0f)));
  // Exactly at the threshold is busy.
  s.band_activity = {0.0f, calm, 0.0f, 0.0f, 0.0f, 0.0f};
  EXPECT_EQ(s.choose_bands(calm), 3u);
  EXPECT_EQ(s.band_swept, (std::vector<std::uint8_t>{1, 1, 1, 0, 0, 0}));

  // The giant's band wakes the bands it shares bodies with, and itself.
  s.band_activity = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.2f};
  EXPECT_EQ(s.choose_bands(calm), 3u);
  EXPECT_EQ(s.band_swept, (std::vector<std::uint8_t>{0, 0, 0, 1, 1, 1}));
}

// Which bands a sweep visits must never change what it computes beyond the threshold: with the
// threshold at the smallest float, only bands that changed no push at all in their last sweep, and
// whose wake ranges changed none either, are left out, and such a band's sweep would change
// nothing. A block of a lattice is packed and pushes its way into a resting lattice (1 cm gaps)
// one row at a time, so bands go from calm to busy as the push arrives: the result must be the
// full sweep's, bit for bit. Narrowing every wake range to the band itself must break that (the
// test can fail).
TEST(CalmBands, LeavingOutBandsThatChangedNothingChangesNoBit) {
  const std::uint32_t cols = 50, rows = 120, packed_rows = 12;
  SolverBodies bodies;
  bodies.resize(cols * rows);
  for (std::uint32_t k = 0; k < cols * rows; ++k) {
    const std::uint32_t row = k / cols;
    // Rows below packed_rows are 0.6 m apart (0.1 m deep); the rest rest 1 cm apart.
    const double y = row < packed_rows ? 0.6 * row : 0.6 * packed_rows + 0.71 * (row - packed_rows);
    set_body(bodies, k, 0.71 * (k % cols), y, 0.35);
  }
  std::vector<SolverPair> pairs;
  add_lattice_pairs(bodies, 0, cols * rows, cols, pairs);
  const std::uint32_t sweeps = 24;
  const float tiniest = std::numeric_limits<float>::denorm_min();
  SolveResult all, exact_skip, narrow_skip;
  const std::vector<float> u_all = scheduled_solve(bodies, pairs, sweeps, 0.0f, false, all);
  const std::vector<float> u_skip = scheduled_solve(bodies, pairs, sweeps, tiniest, false, exact_skip);
  ASSERT_GE(pairs.size(), 5 * kScheduleChunkPairs);
  EXPECT_EQ(all.band_sweeps_skipped, 0u);
  EXPECT_GT(exact_skip.band_sweeps_skipped, 0u);             // the far rows were left out
  EXPECT_EQ(u_skip, u_all);
  EXPECT_EQ(exact_skip.iterations_used, all.iterations_used);
  const std::vector<float> u_narrow = scheduled_solve(bodies, pairs, sweeps, tiniest, true, narrow_skip);
  EXPECT_NE(u_narrow, u_all);
}

// No pairs, and fewer pairs than one band: nothing to skip, nothing to break.
TEST(CalmBands, EmptyAndSingleBandSchedules) {
  const std::vector<SolverPlane> no_planes;
  {
    SolverBodies bodies;
    bodies.resize(3);
    for (std::uint32_t i = 0; i < 3; ++i) set_body(bodies, i, 5.0 * i, 0.0, 0.35);
    bodies.displaced = true;
    std::fill(bodies.u.begin(), bodies.u.end(), 0.0f);
    std::vector<SolverPair> pairs;
    PairSchedule s;
    build_pair_schedule(bodies, pairs, 0.25, s);
    EXPECT_EQ(s.band_count(), 0u);
    const SolveResult r = solve_contacts(bodies, pairs, no_planes, 8, 0, 0.0, 0.25, s, true);
    EXPECT_EQ(r.band_sweeps, 0u);
    EXPECT_EQ(r.max_pen_over_radius, 0.0);
  }
  {
    const std::uint32_t n = 8;
    SolverBodies bodies;
    bodies.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) set_body(bodies, i, 0.6 * i, 0.0, 0.35);  // a squeezed line
    bodies.displaced = true;
    std::fill(bodies.u.begin(), bodies.u.end(), 0.0f);
    std::vector<SolverPair> pairs;
    for (std::uint32_t i = 0; i + 1 < n; ++i) pairs.push_back(grounded_pair(bodies, i, i + 1));
    PairSchedule s;
    build_pair_schedule(bodies, pairs, 0.25, s);
    ASSERT_EQ(s.band_count(), 1u);
    EXPECT_EQ(s.band_wake_lo[0], 0u);
    EXPECT_EQ(s.band_wake_hi[0], 0u);
    const SolveResult r = solve_contacts(bodies, pairs, no_planes, 500, 0, 0.0, 0.25, s, true);
    // The line spreads out (it is free at both ends) until no sweep changes a push by 1e-3 r,
    // long before the budget; the ends move out by about half the 0.7 m of overlap each.
    EXPECT_LT(r.iterations_used, 500u);
    EXPECT_LT(r.max_pen_over_radius, 0.02);
    EXPECT_GT(bodies.u[2 * (n - 1)], 0.25f);
    EXPECT_LT(bodies.u[0], -0.25f);
  }
}

}  // namespace
}  // namespace throng::detail
