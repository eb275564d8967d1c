// A stored state hash, checked on every CI run: the same scene, inputs and code must reproduce the
// same bits on any x86-64 machine (no -march=native, no FMA contraction, no fast-math, no unordered
// iteration). A change that alters the simulation on purpose (solver, broadphase order, policy
// maths) must update kGolden in the same commit and say so; an unexplained change here is a
// determinism bug.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "world/world_fixtures.h"

namespace throng {
namespace {

using namespace throng::test;

std::uint64_t run_reference_scene() {
  WorldSettings s;
  s.iterations = 8;
  World w(s, test_table(), weight_policy(params::PushMode::ratio, 100.0));
  // 600 bodies of three weights on a sunflower spiral (no RNG: the layout is exact arithmetic),
  // all converging on the origin.
  for (int k = 0; k < 600; ++k) {
    const double radius = 0.5 * std::sqrt(static_cast<double>(k) + 0.5);
    const double angle = 2.39996322972865332 * k;
    add_sphere(w, radius * std::cos(angle), radius * std::sin(angle), 0.3 + 0.01 * (k % 7),
               k % 3 == 0 ? "heavy" : (k % 3 == 1 ? "light" : "infantry"));
  }
  for (int t = 0; t < 120; ++t) {
    for (std::size_t i = 0; i < w.body_count(); ++i) {
      const double x = w.pos_x()[i], y = w.pos_y()[i];
      const double d = std::sqrt(x * x + y * y);
      const double speed = d > 0.05 ? 1.5 : 0.0;
      w.set_desired_velocity(w.id_at(i), d > 0.0 ? Vec3{-x / d * speed, -y / d * speed, 0.0} : Vec3{});
    }
    w.step();
  }
  return w.state_hash();
}

TEST(WorldDeterminism, GoldenStateHash) {
  constexpr std::uint64_t kGolden = 0x5faad34c50d5fca5;
  const std::uint64_t h = run_reference_scene();
  std::printf("reference scene state hash: 0x%016llx\n", static_cast<unsigned long long>(h));
  EXPECT_EQ(h, run_reference_scene());
  EXPECT_EQ(h, kGolden);
}

}  // namespace
}  // namespace throng
