#include <gtest/gtest.h>

#include <chrono>

#include "throng/client_sim/bot_metrics.h"

namespace throng::client_sim {
namespace {

using std::chrono::milliseconds;

TEST(BotMetrics, LatencyIsSendToFirstSnapshotCoveringTheSequence) {
  BotMetrics m;
  const TimePoint t0{};
  m.on_launch(t0);
  m.on_command_sent(1, Expect::accept, t0 + milliseconds(100));
  m.on_command_sent(2, Expect::accept, t0 + milliseconds(133));
  m.on_command_sent(3, Expect::reject, t0 + milliseconds(140));   // not measured
  m.on_command_sent(4, Expect::unknown, t0 + milliseconds(150));  // not measured
  m.on_snapshot_received(10, 200, t0 + milliseconds(120));
  m.on_applied_sequence(0, t0 + milliseconds(120));
  EXPECT_EQ(m.latency_ms().size(), 0u);
  m.on_snapshot_received(11, 200, t0 + milliseconds(150));
  m.on_applied_sequence(1, t0 + milliseconds(150));
  ASSERT_EQ(m.latency_ms().size(), 1u);
  EXPECT_NEAR(m.latency_ms().values()[0], 50.0, 1e-6);
  // A later snapshot with a higher applied sequence resolves the rest (a lost command is
  // resolved by the first snapshot at or past its sequence, by definition).
  m.on_snapshot_received(12, 200, t0 + milliseconds(190));
  m.on_applied_sequence(4, t0 + milliseconds(190));
  ASSERT_EQ(m.latency_ms().size(), 2u);
  EXPECT_NEAR(m.latency_ms().values()[1], 57.0, 1e-6);
  EXPECT_EQ(m.commands().sent, 4u);
  EXPECT_EQ(m.commands().expect_accept, 2u);
  EXPECT_EQ(m.commands().expect_reject, 1u);
  EXPECT_EQ(m.commands().expect_unknown, 1u);
  EXPECT_EQ(m.commands().applied, 2u);
  EXPECT_EQ(m.pending_commands(), 0u);
  ASSERT_TRUE(m.join_ms());
  EXPECT_NEAR(*m.join_ms(), 120.0, 1e-6);
  // The progress window hands out what it collected once.
  EXPECT_EQ(m.take_window_latency().size(), 2u);
  EXPECT_EQ(m.take_window_latency().size(), 0u);
}

TEST(BotMetrics, GapsInterArrivalAndBytes) {
  BotMetrics m;
  const TimePoint t0{};
  m.on_snapshot_received(100, 50, t0);
  m.on_snapshot_received(101, 60, t0 + milliseconds(33));
  m.on_snapshot_received(104, 70, t0 + milliseconds(133));  // 102, 103 missed
  m.on_snapshot_received(103, 70, t0 + milliseconds(140));  // late: out of order, not a gap
  m.on_snapshot_received(110, 70, t0 + milliseconds(340));  // 105..109 missed
  EXPECT_EQ(m.snapshots().samples, 5u);
  EXPECT_EQ(m.snapshots().bytes, 320u);
  EXPECT_EQ(m.snapshots().missed_ticks, 7u);
  EXPECT_EQ(m.snapshots().longest_gap_ticks, 5u);  // 105..109, not the sum
  EXPECT_EQ(m.snapshots().out_of_order, 1u);
  ASSERT_EQ(m.interarrival_ms().size(), 4u);
  EXPECT_NEAR(m.interarrival_ms().values()[0], 33.0, 1e-6);
  EXPECT_NEAR(m.interarrival_ms().summary().max, 200.0, 1e-6);
  EXPECT_FALSE(m.join_ms()) << "no launch time given";
}

}  // namespace
}  // namespace throng::client_sim

namespace throng::client_sim {
namespace {

// Staleness: arrivals on the tick clock give 0; a stream that falls further behind (every sample
// arriving, none missed) shows its growing age even though no tick is missed.
TEST(BotMetricsStaleness, ASteadyStreamIsFreshAndOneFallingBehindIsNot) {
  const TimePoint t0{};
  BotMetrics steady, behind;
  steady.set_tick_ms(33.0);
  behind.set_tick_ms(33.0);
  for (std::uint64_t tick = 1; tick <= 100; ++tick) {
    steady.on_snapshot_received(tick, 100, t0 + std::chrono::microseconds(33'000 * tick + 40'000));
    // Every sample arrives, each 2 ms later against the tick clock than the one before.
    behind.on_snapshot_received(tick, 100, t0 + std::chrono::microseconds(35'000 * tick + 40'000));
  }
  EXPECT_EQ(steady.staleness_ms().summary().max, 0.0);
  EXPECT_EQ(behind.snapshots().missed_ticks, 0u);
  EXPECT_NEAR(behind.staleness_ms().summary().max, 198.0, 0.01);  // 99 ticks x 2 ms
  BotMetrics unknown;  // no tick period yet: nothing measured
  unknown.on_snapshot_received(1, 100, t0);
  EXPECT_EQ(unknown.staleness_ms().summary().count, 0u);
}

}  // namespace
}  // namespace throng::client_sim
