#include "throng/params/soft_push.h"

#include <gtest/gtest.h>

#include <limits>

namespace throng::params {
namespace {

constexpr double kRadius_m = 0.4;

TEST(ParamsSoftPush, RigidWhenSoftnessIsZero) {
  for (double d : {1e-6, 0.01, 0.4, 3.0}) EXPECT_EQ(soft_push_share(0.0, d, kRadius_m), 1.0);
}

TEST(ParamsSoftPush, DegenerateInputBehavesRigid) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(soft_push_share(nan, 0.1, kRadius_m), 1.0);
  EXPECT_EQ(soft_push_share(0.5, nan, kRadius_m), 1.0);
  EXPECT_EQ(soft_push_share(0.5, 0.0, kRadius_m), 1.0);
  EXPECT_EQ(soft_push_share(0.5, 0.1, 0.0), 1.0);
  EXPECT_EQ(soft_push_share(0.5, 0.1, std::numeric_limits<double>::infinity()), 1.0);
}

TEST(ParamsSoftPush, ShareAndPushGrowWithDepth) {
  for (double s : {0.1, 0.3, 0.6, 0.9, 1.0}) {
    double prev_share = 0.0;
    double prev_push = 0.0;
    for (int i = 1; i <= 4000; ++i) {
      const double d = kRadius_m * 1e-3 * i;  // up to 4 radii
      const double share = soft_push_share(s, d, kRadius_m);
      const double push = d * share;
      EXPECT_GT(share, prev_share) << "s=" << s << " d=" << d;
      EXPECT_GT(push, prev_push) << "s=" << s << " d=" << d;
      EXPECT_GT(share, 0.0);
      EXPECT_LE(share, 1.0);
      prev_share = share;
      prev_push = push;
    }
  }
}

TEST(ParamsSoftPush, NeverSinksDeeperThanMaxSink) {
  for (double s : {0.1, 0.5, 1.0}) {
    const double max_sink = soft_max_sink_m(s, kRadius_m);
    EXPECT_DOUBLE_EQ(max_sink, s * kRadius_m);
    for (double d = 1e-4; d < 1000.0 * kRadius_m; d *= 1.5) {
      const double remaining = d * (1.0 - soft_push_share(s, d, kRadius_m));
      EXPECT_LE(remaining, max_sink) << "s=" << s << " d=" << d;
      EXPECT_LT(remaining, d);
    }
  }
}

// Left alone (nothing presses further in), the mover comes out gradually: not in one tick, but
// geometrically fast for a medium softness.
TEST(ParamsSoftPush, ConvergesGraduallyOverSeveralTicks) {
  const double s = 0.5;
  double d = kRadius_m;  // start one radius deep
  const double start = d;
  int ticks_to_one_percent = 0;
  for (int tick = 1; tick <= 200; ++tick) {
    const double next = d * (1.0 - soft_push_share(s, d, kRadius_m));
    EXPECT_LT(next, d);
    EXPECT_GT(next, 0.0);
    EXPECT_LE(next, s * d);        // at least the factor s per tick ...
    if (d <= kRadius_m) {
      EXPECT_GE(next, 0.5 * s * d);  // ... and at most s/2: never all at once
    }
    d = next;
    if (ticks_to_one_percent == 0 && d < 0.01 * start) ticks_to_one_percent = tick;
  }
  EXPECT_GE(ticks_to_one_percent, 3);
  EXPECT_LT(d, 1e-12 * start);
  // The first tick leaves a visible part of the depth.
  EXPECT_GT(start * (1.0 - soft_push_share(s, start, kRadius_m)), 0.1 * start);
}

}  // namespace
}  // namespace throng::params
