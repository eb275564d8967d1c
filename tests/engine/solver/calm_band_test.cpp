// A scheduled solve leaves out the bands of its schedule that nothing near has pushed in the last
// sweep (solver/pair_schedule.h, kCalmPushOverRadius). Two things must hold: a band is visited
// whenever a band sharing a body with it pushed (the wake ranges cover every shared body), and a
// band left out had nothing to do (leaving out a resting crowd changes no bit).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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

// Every pair of bands that share a body lies in each other's wake range, on random pair lists
// with a few "giants" that pairs all over the list touch.
TEST(CalmBands, WakeRangesCoverEveryBandSharingABody) {
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const std::uint32_t n = 3000;
    SolverBodies bodies;
    bodies.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) set_body(bodies, i, 0.7 * (i % 60), 0.7 * (i / 60), 0.35);
    std::vector<SolverPair> pairs;
    const std::size_t count = 3 * kScheduleChunkPairs + rng() % kScheduleChunkPairs;
    for (std::size_t k = 0; k < count; ++k) {
      // Mostly local pairs in list order (a crowd), sometimes a pair with one of five giants.
      const std::uint32_t a = static_cast<std::uint32_t>(k * n / count);
      const std::uint32_t b = rng() % 50 == 0 ? static_cast<std::uint32_t>(rng() % 5)
                                              : std::min<std::uint32_t>(n - 1, a + 1 + static_cast<std::uint32_t>(rng() % 70));
      if (a != b) pairs.push_back(grounded_pair(bodies, a, b));
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
  for (std::uint32_t k = 0; k < rest; ++k) {
    if (k % rest_side + 1 < rest_side) pairs.push_back(grounded_pair(bodies, jam + k, jam + k + 1));
    if (k + rest_side < rest) pairs.push_back(grounded_pair(bodies, jam + k, jam + k + rest_side));
  }
  const std::vector<SolverPlane> no_planes;
  const std::uint32_t sweeps = 8;

  auto run = [&](float calm, SolveResult& result) {
    SolverBodies b = bodies;
    std::vector<SolverPair> p = pairs;
    b.displaced = true;
    std::fill(b.u.begin(), b.u.end(), 0.0f);
    PairSchedule s;
    build_pair_schedule(b, p, 0.25, s);
    s.calm_push_over_radius = calm;
    result = solve_contacts(b, p, no_planes, sweeps, 0.0, 0.25, s, true);
    return b.u;
  };
  SolveResult all, skipping;
  const std::vector<float> u_all = run(0.0f, all);
  const std::vector<float> u_skipping = run(kCalmPushOverRadius, skipping);

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

}  // namespace
}  // namespace throng::detail
