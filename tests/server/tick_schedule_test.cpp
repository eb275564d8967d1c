// The tick schedule's rules with synthetic times: no drift, overruns counted, bounded catch-up.
#include "throng/server/tick_schedule.h"

#include <gtest/gtest.h>

namespace throng::server {
namespace {

using namespace std::chrono_literals;
using TP = TickSchedule::TimePoint;

TEST(TickSchedule, DeadlinesAreAbsoluteSoLateWakeupsDoNotDrift) {
  const TP t0{};
  TickSchedule s(33'333'333ns, 3, t0);
  // Every tick wakes 2 ms late and takes 1 ms: deadlines still advance by exactly one period.
  for (int i = 0; i < 300; ++i) {
    const TP due = s.next_deadline();
    s.begin_tick(due + 2ms);
    EXPECT_FALSE(s.end_tick(due + 3ms));
  }
  EXPECT_EQ(s.next_deadline(), t0 + 300 * 33'333'333ns);
  EXPECT_EQ(s.overruns(), 0u);
  EXPECT_EQ(s.skipped(), 0u);
}

TEST(TickSchedule, ATickEndingAfterTheNextDeadlineIsAnOverrun) {
  TickSchedule s(10ms, 3, TP{});
  s.begin_tick(TP{});
  EXPECT_TRUE(s.end_tick(TP{} + 11ms));
  EXPECT_EQ(s.overruns(), 1u);
  // The next tick is due at 10 ms (already past): it runs at once, catch-up, no skip.
  EXPECT_EQ(s.next_deadline(), TP{} + 10ms);
  s.begin_tick(TP{} + 11ms);
  EXPECT_FALSE(s.end_tick(TP{} + 12ms));
  EXPECT_EQ(s.skipped(), 0u);
}

TEST(TickSchedule, CatchUpIsBoundedAndTheRestIsSkipped) {
  TickSchedule s(10ms, 3, TP{});
  // A 1-second stall before the first tick ends: 100 periods behind.
  s.begin_tick(TP{} + 1000ms);
  // 99 periods behind after advancing once; 3 may be caught up, 96 are skipped.
  EXPECT_EQ(s.skipped(), 96u);
  EXPECT_EQ(s.next_deadline(), TP{} + 970ms);
  int back_to_back = 0;
  while (s.next_deadline() < TP{} + 1000ms) {  // overdue ticks only
    s.begin_tick(TP{} + 1000ms);
    ++back_to_back;
  }
  EXPECT_EQ(back_to_back, 3);
  EXPECT_EQ(s.skipped(), 96u);
}

TEST(TickSchedule, RejectsANonPositivePeriod) {
  EXPECT_THROW(TickSchedule(0ms, 3, TP{}), std::invalid_argument);
}

}  // namespace
}  // namespace throng::server
