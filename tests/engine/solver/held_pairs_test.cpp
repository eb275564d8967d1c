// mark_held_fast_pairs (pair_schedule_build.h): the held test and the clamp, four pairs at a time
// in SSE and one at a time past the last group of four, must give the bits of the scalar rule
// (held_by_neighbours in float, std::clamp) for every pair, wherever a range starts and ends.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <random>
#include <vector>

#include "solver/pair_schedule_build.h"

namespace throng::detail {
namespace {

TEST(HeldFastPairs, VectorAndScalarPathsGiveTheScalarRulesBits) {
  constexpr std::uint32_t n = 4 * 64 + 3;
  PairSchedule s;
  s.conflict_lo = 0.35f;
  s.conflict_hi = 0.65f;
  s.lambda.resize(n);
  s.pen0.resize(n);
  s.inv_r_min.resize(n);
  s.share_now.resize(n);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> push(0.0f, 0.3f), pen(-0.2f, 0.3f), share(0.0f, 1.0f);
  for (std::uint32_t f = 0; f < n; ++f) {
    s.lambda[f] = push(rng);
    s.pen0[f] = pen(rng);
    s.inv_r_min[f] = 1.0f / 0.35f;
    s.share_now[f] = share(rng);
  }
  // Edge cases: a negative zero start penetration, no push (padding), shares at and past the
  // bounds, a pair exactly at the margin.
  s.pen0[5] = -0.0f;
  s.lambda[6] = 0.0f;
  s.pen0[6] = -1.0f;
  s.inv_r_min[6] = 0.0f;
  s.share_now[7] = s.conflict_lo;
  s.share_now[8] = 1.0f;
  s.lambda[8] = 0.3f;
  s.pen0[8] = 0.0f;
  s.lambda[9] = static_cast<float>(kHeldPushMarginOverRadius) / s.inv_r_min[9];
  s.pen0[9] = 0.0f;
  const std::vector<float> before = s.share_now;
  auto expected = [&](std::uint32_t f) {
    return held_by_neighbours(s.lambda[f], s.pen0[f], s.inv_r_min[f]) ? std::clamp(before[f], s.conflict_lo, s.conflict_hi)
                                                                  : before[f];
  };
  std::uint32_t held = 0;
  for (const auto& [begin, end] : {std::pair{0u, n}, std::pair{1u, n - 1}, std::pair{3u, 6u}}) {
    s.share_now = before;
    mark_held_fast_pairs(s, begin, end);
    for (std::uint32_t f = 0; f < n; ++f) {
      const float want = f >= begin && f < end ? expected(f) : before[f];
      ASSERT_EQ(std::bit_cast<std::uint32_t>(s.share_now[f]), std::bit_cast<std::uint32_t>(want))
          << "pair " << f << " of range [" << begin << ", " << end << ")";
      if (begin == 0 && s.share_now[f] != before[f]) ++held;
    }
  }
  EXPECT_GT(held, n / 8);  // the draw clamps many pairs, so the comparison means something
  EXPECT_EQ(s.share_now[8], 1.0f);  // only the last range ran: pair 8 is outside it
}

}  // namespace
}  // namespace throng::detail
