// The vectorised whole-crowd passes (world/body_passes.cpp, compiled with -fno-trapping-math)
// must compute exactly what the scalar formulas compute: the state hash of every scene without
// scenery depends on it. Compared bit for bit against a plain reference on random bodies,
// grounded and airborne, pushed with and against their step, with and without carry, and on
// counts that leave a vector remainder.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "world/body_passes.h"

namespace throng::detail {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

struct Crowd {
  std::vector<double> x, y, z, vx, vy, vz, push_x, push_y;
  std::vector<std::uint8_t> grounded;
  std::vector<double> sx, sy, sz, mx, my;

  explicit Crowd(std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(-1e4, 1e4), vel(-3.0, 3.0), push(-0.05, 0.05);
    for (auto* v : {&x, &y, &z, &vx, &vy, &vz, &push_x, &push_y, &sx, &sy, &sz, &mx, &my}) v->resize(n);
    grounded.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      x[i] = pos(rng); y[i] = pos(rng); z[i] = pos(rng) * 1e-3;
      vx[i] = vel(rng); vy[i] = vel(rng); vz[i] = vel(rng);
      push_x[i] = push(rng); push_y[i] = push(rng);
      grounded[i] = static_cast<std::uint8_t>(rng() % 2);
    }
    // Edge cases: standing still, a push exactly against the step, a push larger than the step.
    if (n > 3) {
      vx[0] = vy[0] = 0.0;
      push_x[1] = -vx[1] * 0.01; push_y[1] = -vy[1] * 0.01;
      push_x[2] = -vx[2]; push_y[2] = -vy[2];
    }
  }
  MoveColumns move_columns() {
    return {x.data(), y.data(), z.data(), vx.data(), vy.data(), vz.data(), push_x.data(), push_y.data(), grounded.data(),
            sx.data(), sy.data(), sz.data(), mx.data(), my.data()};
  }
};

TEST(BodyPasses, MoveMatchesTheScalarFormulaBitForBit) {
  const double dt = 1.0 / 60.0;
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{1001}}) {
    for (const double carry : {0.0, 0.9, 1.0}) {
      Crowd c(n, static_cast<std::uint32_t>(n * 10 + carry * 10));
      const Crowd before = c;
      move_free_bodies(c.move_columns(), n, dt, carry);
      for (std::size_t i = 0; i < n; ++i) {
        double dx = before.vx[i] * dt, dy = before.vy[i] * dt;
        if (carry > 0.0) {
          // The formula as the scalar loop wrote it before the kernel, with std::clamp.
          const double step2 = dx * dx + dy * dy;
          const double blocked_times_step =
              std::clamp(-(before.push_x[i] * dx + before.push_y[i] * dy), 0.0, step2);
          const double keep = 1.0 - carry * blocked_times_step / (step2 > 0.0 ? step2 : 1.0);
          dx *= keep;
          dy *= keep;
        }
        const double dz = before.grounded[i] ? 0.0 : before.vz[i] * dt;
        ASSERT_TRUE(same_bits(c.x[i], before.x[i] + dx)) << "n " << n << " carry " << carry << " body " << i;
        ASSERT_TRUE(same_bits(c.y[i], before.y[i] + dy)) << "body " << i;
        ASSERT_TRUE(same_bits(c.z[i], before.z[i] + dz)) << "body " << i;
        ASSERT_TRUE(same_bits(c.sx[i], before.x[i]) && same_bits(c.sy[i], before.y[i]) && same_bits(c.sz[i], before.z[i]));
        ASSERT_TRUE(same_bits(c.mx[i], c.x[i]) && same_bits(c.my[i], c.y[i]));
      }
    }
  }
}

TEST(BodyPasses, CarryOnlyEverShortensTheStep) {
  // keep = 1 - carry * clamp(blocked, 0, step) / step: in [1 - carry, 1], 1 when not pushed back.
  EXPECT_EQ(carried_step_share(0.02, 0.0, 0.01, 0.0, 0.9), 1.0);    // pushed along the step
  EXPECT_EQ(carried_step_share(0.02, 0.0, -1.0, 0.0, 0.9), 1.0 - 0.9);  // pushed back by more than it
  EXPECT_EQ(carried_step_share(0.0, 0.0, -1.0, 0.0, 0.9), 1.0);     // no step
  const double half = carried_step_share(0.02, 0.0, -0.01, 0.0, 1.0);  // pushed back by half the step
  EXPECT_DOUBLE_EQ(half, 0.5);
}

TEST(BodyPasses, FinishMatchesTheScalarFormulaBitForBit) {
  const std::size_t n = 515;
  Crowd c(n, 7);
  std::vector<double> qx(n), qy(n), ax(n), ay(n), az(n);
  // Start and moved positions a little off the final ones.
  for (std::size_t i = 0; i < n; ++i) {
    c.sx[i] = c.x[i] - c.vx[i] * 0.01; c.sy[i] = c.y[i] - c.vy[i] * 0.01; c.sz[i] = c.z[i] - c.vz[i] * 0.01;
    c.mx[i] = c.x[i] - c.push_x[i]; c.my[i] = c.y[i] - c.push_y[i];
  }
  const double inv_dt = 60.0;
  finish_bodies({c.x.data(), c.y.data(), c.z.data(), c.mx.data(), c.my.data(), c.sx.data(), c.sy.data(), c.sz.data(),
                 qx.data(), qy.data(), ax.data(), ay.data(), az.data()},
                n, inv_dt);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_TRUE(same_bits(qx[i], c.x[i] - c.mx[i]) && same_bits(qy[i], c.y[i] - c.my[i])) << "body " << i;
    ASSERT_TRUE(same_bits(ax[i], (c.x[i] - c.sx[i]) * inv_dt)) << "body " << i;
    ASSERT_TRUE(same_bits(ay[i], (c.y[i] - c.sy[i]) * inv_dt)) << "body " << i;
    ASSERT_TRUE(same_bits(az[i], (c.z[i] - c.sz[i]) * inv_dt)) << "body " << i;
  }
}

}  // namespace
}  // namespace throng::detail
