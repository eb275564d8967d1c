// Re-simulation: a recorded match verifies; tampered hashes, torn tails and writer gaps are
// reported at the right tick.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "matchlog_test_util.h"
#include "throng/matchlog/reader.h"
#include "throng/matchlog/replay.h"
#include "throng/world/world.h"

namespace throng::matchlog {
namespace {

// One played match shared by the tests of this file (playing it is the slow part).
const test::PlayedMatch& played() {
  static const test::PlayedMatch p = test::play_match(200);
  return p;
}

TEST(Verify, RecordedMatchVerifiesEveryTick) {
  const auto& p = played();
  // The match exercised what the log must carry.
  EXPECT_EQ(p.joins_accepted, 6u);
  EXPECT_GT(p.commands_accepted, 500u);
  EXPECT_GT(p.commands_rejected, 50u);

  const auto path = test::test_dir() / "match.tlog";
  test::write_played(path, p.ticks, test::match_header());
  MatchLogReader r(path.string());
  ASSERT_EQ(r.scan().end, LogEnd::closed) << r.scan().problem;
  ASSERT_EQ(r.scan().ticks, 200u);
  TickRecord t;
  for (std::size_t i = 0; r.next(t); ++i) ASSERT_EQ(t.state_hash, p.ticks[i].state_hash);

  std::uint64_t progress_calls = 0, last_done = 0;
  const VerifyResult v = verify_log(r, [&](std::uint64_t done, std::uint64_t total) {
    ++progress_calls;
    last_done = done;
    EXPECT_EQ(total, 200u);
  });
  EXPECT_TRUE(v.all_match());
  EXPECT_FALSE(v.mismatch);
  EXPECT_EQ(v.ticks_verified, 200u);
  EXPECT_EQ(v.ticks_total, 200u);
  EXPECT_GT(v.ticks_per_second, 0.0);
  EXPECT_GT(v.realtime_factor, 0.0);
  EXPECT_GE(progress_calls, 6u);
  EXPECT_EQ(last_done, 200u);

  // The same with the logged interest settings (the default replays with a 1 cm radius).
  ResimOptions exact;
  exact.exact_interest = true;
  const VerifyResult e = verify_log(r, {}, 30, exact);
  EXPECT_TRUE(e.all_match());
  EXPECT_EQ(e.ticks_verified, 200u);
}

TEST(Verify, TamperedHashFailsAtThatTick) {
  const auto& p = played();
  const auto path = test::test_dir() / "tampered.tlog";
  test::write_played(path, p.ticks, test::match_header(), {}, 57);
  MatchLogReader r(path.string());
  const VerifyResult v = verify_log(r);
  EXPECT_FALSE(v.all_match());
  ASSERT_TRUE(v.mismatch);
  EXPECT_EQ(v.mismatch_tick, 57u);
  EXPECT_EQ(v.ticks_verified, 56u);
  EXPECT_EQ(v.expected_hash, p.ticks[56].state_hash ^ 1ull);
  EXPECT_EQ(v.actual_hash, p.ticks[56].state_hash);
}

TEST(Verify, DroppedInputMakesTheReSimulationDiverge) {
  // A log that lost one command (or any input) must not verify: the inputs are what is checked.
  const auto& p = played();
  auto ticks = p.ticks;
  for (auto& t : ticks) {
    if (t.tick >= 60 && !t.inputs.commands.empty()) {
      t.inputs.commands.erase(t.inputs.commands.begin());
      break;
    }
  }
  const auto path = test::test_dir() / "lost.tlog";
  test::write_played(path, ticks, test::match_header());
  MatchLogReader r(path.string());
  const VerifyResult v = verify_log(r);
  EXPECT_TRUE(v.mismatch);
  EXPECT_GE(v.mismatch_tick, 60u);
}

TEST(Verify, TornLogVerifiesUpToTheLastCompleteTick) {
  const auto& p = played();
  const auto dir = test::test_dir();
  test::write_played(dir / "full.tlog", p.ticks, test::match_header());
  const auto bytes = test::read_bytes(dir / "full.tlog");
  test::write_bytes(dir / "torn.tlog", bytes, bytes.size() * 2 / 3);  // kill -9 mid-write
  MatchLogReader r((dir / "torn.tlog").string());
  ASSERT_EQ(r.scan().end, LogEnd::torn);
  ASSERT_GT(r.scan().ticks, 100u);
  const VerifyResult v = verify_log(r);
  EXPECT_TRUE(v.all_match());
  EXPECT_EQ(v.ticks_verified, r.scan().ticks);
}

TEST(Verify, PushEventRecordingDoesNotChangeTheHash) {
  // export turns record_push_events on; a match recorded with it off must still re-simulate.
  scene::SceneDef quiet = test::small_battle();
  quiet.settings.record_push_events = false;
  const auto p = test::play_match(120, quiet);
  const auto path = test::test_dir() / "quiet.tlog";
  test::write_played(path, p.ticks, test::match_header(quiet));
  MatchLogReader r(path.string());
  EXPECT_FALSE(r.header().scene.settings.record_push_events);
  ResimOptions ro;
  ro.record_push_events = true;
  Resimulator sim(r.header(), ro);
  TickRecord t;
  std::size_t events = 0;
  while (r.next(t)) {
    const std::uint64_t expected = t.state_hash;
    ASSERT_EQ(sim.step(t), expected) << "tick " << sim.tick();
    events += sim.match().world().push_events().size();
  }
  EXPECT_GT(events, 0u);
}

TEST(Verify, WriterGapStopsTheVerificationThere) {
  // A writer whose disk cannot keep up and whose spill cap is tiny drops ticks (counted, gap
  // records); verify must stop at the first missing tick instead of re-simulating across it.
  const auto& p = played();
  const auto path = test::test_dir() / "gap.tlog";
  WriterOptions o;
  o.block_ticks = 1;
  o.ring_slots = 4;
  o.spill_cap_bytes = 2000;
  o.test_write_delay_ms = 20;
  o.fsync_interval_ms = 0;
  MatchLogWriter w(path.string(), o);
  w.begin(test::match_header());
  for (const TickRecord& t : p.ticks) {
    w.append_tick(t.tick, t.inputs, t.state_hash, t.flags);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));  // ticks keep coming while the disk lags
  }
  const WriterStats before_close = w.stats();
  w.close();
  const WriterStats s = w.stats();
  ASSERT_GT(s.ticks_dropped, 0u);
  EXPECT_EQ(s.ticks_written + s.ticks_dropped, 200u);
  EXPECT_GE(before_close.backlog_high_water, 4u);

  MatchLogReader r(path.string());
  EXPECT_EQ(r.scan().end, LogEnd::closed) << r.scan().problem;
  EXPECT_EQ(r.scan().ticks_missing, s.ticks_dropped);
  EXPECT_EQ(r.scan().ticks, s.ticks_written);
  ASSERT_FALSE(r.scan().gaps.empty());
  const std::uint64_t first_missing = r.scan().gaps.front().first_tick;
  const VerifyResult v = verify_log(r);
  EXPECT_TRUE(v.stopped_at_gap);
  EXPECT_FALSE(v.mismatch);
  EXPECT_EQ(v.gap_first_tick, first_missing);
  EXPECT_EQ(v.ticks_verified, first_missing - 1);
  EXPECT_FALSE(v.all_match());
  // Ticks after the gap are still readable (for info / inspection), just not re-simulatable.
  EXPECT_GT(r.scan().last_tick, first_missing);
}

TEST(Verify, RealMatchLogsAreIdenticalApartFromTheHeaderTime) {
  const auto& p = played();
  const auto dir = test::test_dir();
  test::write_played(dir / "a.tlog", p.ticks, test::match_header());
  const auto again = test::play_match(200);  // the same match played again from scratch
  test::write_played(dir / "b.tlog", again.ticks, test::match_header());
  const auto a = test::read_bytes(dir / "a.tlog"), b = test::read_bytes(dir / "b.tlog");
  ASSERT_EQ(a.size(), b.size());
  const std::size_t header = MatchLogReader((dir / "a.tlog").string()).scan().header_bytes;
  EXPECT_TRUE(std::equal(a.begin() + static_cast<std::ptrdiff_t>(header), a.end(), b.begin() + static_cast<std::ptrdiff_t>(header)));
}

}  // namespace
}  // namespace throng::matchlog
