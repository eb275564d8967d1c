// The end-of-match rules' timer with synthetic times: begins, holds, elapses at the limit, and
// starts over after the condition lapsed.
#include "throng/server/held_for.h"

#include <gtest/gtest.h>

namespace throng::server {
namespace {

using namespace std::chrono_literals;
using State = HeldFor::State;

TEST(HeldFor, ElapsesOnceTheConditionHeldForTheLimitAndStartsOverAfterALapse) {
  const HeldFor::Clock::time_point t0{};
  HeldFor h;
  EXPECT_EQ(h.update(false, t0, 2.0), State::off);
  EXPECT_EQ(h.update(true, t0 + 1s, 2.0), State::began);
  EXPECT_EQ(h.update(true, t0 + 2s, 2.0), State::holding);
  EXPECT_EQ(h.update(true, t0 + 2999ms, 2.0), State::holding);
  EXPECT_EQ(h.update(false, t0 + 3500ms, 2.0), State::ended);
  EXPECT_EQ(h.update(false, t0 + 4s, 2.0), State::off);
  // Counted from where it began again, not from the first time.
  EXPECT_EQ(h.update(true, t0 + 5s, 2.0), State::began);
  EXPECT_EQ(h.update(true, t0 + 6s, 2.0), State::holding);
  EXPECT_EQ(h.update(true, t0 + 7s, 2.0), State::elapsed);
  EXPECT_EQ(h.update(true, t0 + 8s, 2.0), State::elapsed);
}

}  // namespace
}  // namespace throng::server
