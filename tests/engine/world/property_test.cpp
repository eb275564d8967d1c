// Property tests over random scenes (fixed seeds, own uniform mapping so every platform draws the
// same numbers): resolved pairs never end deeper, fixed bodies never move, shares stay in range,
// and the same inputs give the same hash.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "world/world_fixtures.h"

namespace throng {
namespace {

using namespace throng::test;

double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0));
}

World random_scene(std::uint64_t seed, std::size_t n, double extent) {
  std::mt19937_64 rng(seed);
  World w(WorldSettings{}, test_table(), weight_policy(params::PushMode::ratio, 50.0));
  const char* archetypes[] = {"infantry", "light", "heavy"};
  for (std::size_t i = 0; i < n; ++i) {
    BodyDef d;
    d.radius_m = uniform(rng, 0.2, 0.8);
    d.half_height_m = uniform(rng, 0.0, 0.5);
    d.position = {uniform(rng, -extent, extent), uniform(rng, -extent, extent), d.radius_m + d.half_height_m};
    d.archetype = archetypes[rng() % 3];
    const ObjectId id = w.create_body(d);
    w.set_desired_velocity(id, {uniform(rng, -2.0, 2.0), uniform(rng, -2.0, 2.0), 0.0});
  }
  return w;
}

// Isolated pairs (far apart from everything else): after a tick with no motion, each pair is no
// deeper than it started, and its push split matches the share in (0, 1).
TEST(WorldProperty, IsolatedPairsNeverEndDeeper) {
  std::mt19937_64 rng(7);
  World w(WorldSettings{}, test_table(), weight_policy(params::PushMode::ratio, 50.0));
  struct P { ObjectId a, b; double depth; };
  std::vector<P> pairs;
  for (int i = 0; i < 500; ++i) {
    const double ra = uniform(rng, 0.01, 2.0), rb = uniform(rng, 0.01, 2.0);
    const double d = uniform(rng, 0.0, ra + rb);
    const double ang = uniform(rng, 0.0, 6.283185307179586);
    const double cx = 20.0 * (i % 25), cy = 20.0 * (i / 25);
    BodyDef da, db;
    da.radius_m = ra; db.radius_m = rb;
    da.position = {cx, cy, ra};
    db.position = {cx + d * std::cos(ang), cy + d * std::sin(ang), rb};
    da.archetype = (i % 2) ? "light" : "heavy";
    pairs.push_back({w.create_body(da), w.create_body(db), std::max(0.0, ra + rb - d)});
  }
  w.step();
  for (const P& p : pairs) {
    const Vec3 a = w.position(p.a), b = w.position(p.b);
    // Both rest on the ground, so different radii put the centres at different heights.
    const double dist = std::sqrt((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y) + (b.z - a.z) * (b.z - a.z));
    std::size_t ia = 0, ib = 0;
    for (std::size_t k = 0; k < w.body_count(); ++k) {
      if (w.id_at(k) == p.a) ia = k;
      if (w.id_at(k) == p.b) ib = k;
    }
    const double depth_after = std::max(0.0, w.radius()[ia] + w.radius()[ib] - dist);
    EXPECT_LE(depth_after, p.depth + 1e-12);
    EXPECT_LE(depth_after, 1e-9);
  }
  for (const PushEvent& e : w.push_events()) {
    EXPECT_GT(e.share_a, 0.0f);
    EXPECT_LT(e.share_a, 1.0f);
  }
}

// Sum of the penetration depths over all pairs, by brute force (independent of the solver).
double total_penetration(const World& w) {
  const auto x = w.pos_x(), y = w.pos_y(), z = w.pos_z(), r = w.radius(), hh = w.half_height();
  double sum = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    for (std::size_t j = i + 1; j < x.size(); ++j) {
      const double gap = std::max(0.0, std::fabs(z[j] - z[i]) - hh[i] - hh[j]);
      const double d = std::sqrt((x[j] - x[i]) * (x[j] - x[i]) + (y[j] - y[i]) * (y[j] - y[i]) + gap * gap);
      sum += std::max(0.0, r[i] + r[j] - d);
    }
  }
  return sum;
}

// Random crowds with random velocities and a fixed wall: no body ends inside the rigid wall, no
// NaN, shares stay in [0, 1], and once the crowd stops the remaining overlap is worked off.
TEST(WorldProperty, RandomScenesStayConsistent) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    World w = random_scene(seed, 400, 12.0);
    const ObjectId wall = w.add_fixed_box({0.0, 0.0, 1.0}, {0.2, 4.0, 1.0}, 0.3);
    for (int t = 0; t < 30; ++t) w.step();
    EXPECT_TRUE(w.is_fixed(wall));
    for (std::size_t i = 0; i < w.body_count(); ++i) {
      EXPECT_LE(w.scenery_max_penetration(i), 1e-6) << "seed " << seed;
      ASSERT_TRUE(std::isfinite(w.pos_x()[i]) && std::isfinite(w.pos_y()[i]));
    }
    for (const PushEvent& e : w.push_events()) {
      EXPECT_GE(e.share_a, 0.0f);
      EXPECT_LE(e.share_a, 1.0f);
    }
    for (std::size_t i = 0; i < w.body_count(); ++i) w.set_desired_velocity(w.id_at(i), {0.0, 0.0, 0.0});
    w.step();
    const double after_first_still_tick = total_penetration(w);
    for (int t = 0; t < 30; ++t) w.step();
    EXPECT_LE(total_penetration(w), after_first_still_tick + 1e-12) << "seed " << seed;
    EXPECT_LT(total_penetration(w), 1e-3 * static_cast<double>(w.body_count())) << "seed " << seed;
  }
}

TEST(WorldProperty, SameInputsGiveSameHashEveryTick) {
  for (std::uint64_t seed = 11; seed <= 13; ++seed) {
    World a = random_scene(seed, 1000, 10.0);
    World b = random_scene(seed, 1000, 10.0);
    EXPECT_EQ(a.state_hash(), b.state_hash());
    for (int t = 0; t < 60; ++t) {
      a.step();
      b.step();
      ASSERT_EQ(a.state_hash(), b.state_hash()) << "seed " << seed << " tick " << t;
    }
  }
}

TEST(WorldProperty, DifferentInputsGiveDifferentHashes) {
  World a = random_scene(21, 200, 5.0);
  World b = random_scene(21, 200, 5.0);
  b.set_desired_velocity(b.id_at(17), {0.5, 0.0, 0.0});
  a.step();
  b.step();
  EXPECT_NE(a.state_hash(), b.state_hash());
}

}  // namespace
}  // namespace throng
