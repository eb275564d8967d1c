// The seed's problem statement, measured: when the priority of two pushing bodies flips as the
// game state changes, the conventional priority baseline makes the pair lurch back and forth; the
// continuous push ratio does not.
//
// Oscillation metric: back-and-forth travel of the pair's midpoint along the push axis, i.e. its
// total variation minus its net displacement (metres). A pair that drifts steadily scores 0.
#include <gtest/gtest.h>

#include <cmath>

#include "world/world_fixtures.h"

namespace throng {
namespace {

using namespace throng::test;

double oscillation(params::PushMode mode) {
  params::Term importance;
  importance.input = params::TermInput::importance;
  importance.weight = 1.0;
  importance.scale = 1.0;
  World w(quiet_settings(), test_table(), params::PushPolicy(mode, {importance}, {}));
  const ObjectId a = add_sphere(w, -0.4, 0.0);
  const ObjectId b = add_sphere(w, 0.4, 0.0);
  w.set_param(b, params::Param::importance, 5.0);
  double travel = 0.0;
  double first_mid = 0.0, last_mid = 0.0;
  for (int t = 0; t < 300; ++t) {
    // Game state: a's importance wobbles just around b's (a buff that comes and goes every 7
    // ticks). A priority only sees the sign of the difference; a ratio sees its size.
    w.set_param(a, params::Param::importance, (t / 7) % 2 == 0 ? 5.1 : 4.9);
    w.set_desired_velocity(a, {1.0, 0.0, 0.0});
    w.set_desired_velocity(b, {-1.0, 0.0, 0.0});
    w.step();
    const double mid = 0.5 * (w.position(a).x + w.position(b).x);
    if (t == 0) first_mid = mid;
    else travel += std::fabs(mid - last_mid);
    last_mid = mid;
  }
  return travel - std::fabs(last_mid - first_mid);
}

TEST(WorldOscillation, RatioDoesNotOscillateWherePriorityDoes) {
  const double priority = oscillation(params::PushMode::priority);
  const double ratio = oscillation(params::PushMode::ratio);
  // Priority: the loser is pushed back 100% every tick, so the pair walks ~1/60 m per tick in the
  // current winner's direction and turns round every 7 ticks: ~4.5 m of back-and-forth in 5 s.
  EXPECT_GT(priority, 2.0);
  // Ratio: shares 0.475/0.525, so the midpoint moves 0.05 * (2/60) m per tick: 20x less.
  EXPECT_LT(ratio, 0.1 * priority);
}

}  // namespace
}  // namespace throng
