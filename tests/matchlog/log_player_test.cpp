// LogPlayer: stepping, seeking forwards and backwards, the outbox it exposes, and where it stops.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "matchlog_test_util.h"
#include "throng/matchlog/log_player.h"

namespace throng::matchlog {
namespace {

const test::PlayedMatch& played() {
  static const test::PlayedMatch p = test::play_match(200);
  return p;
}

std::filesystem::path recorded_log(WriterOptions o = {}) {
  const auto path = test::test_dir() / "match.tlog";
  test::write_played(path, played().ticks, test::match_header(), o);
  return path;
}

TEST(LogPlayer, StepsThroughEveryTickWithTheLoggedHashes) {
  const auto& p = played();
  LogPlayer player(recorded_log().string());
  EXPECT_EQ(player.first_tick(), 1u);
  EXPECT_EQ(player.last_tick(), 200u);
  EXPECT_EQ(player.tick(), 0u);
  EXPECT_EQ(player.tick_hz(), 30u);
  EXPECT_TRUE(player.last_hash_matched());
  EXPECT_EQ(player.last_report().tick, 0u);
  std::size_t max_snapshots = 0;
  for (std::uint64_t t = 1; t <= 200; ++t) {
    ASSERT_TRUE(player.step());
    ASSERT_EQ(player.tick(), t);
    ASSERT_TRUE(player.last_hash_matched()) << "tick " << t;
    ASSERT_EQ(player.match().state_hash(), p.ticks[t - 1].state_hash);
    ASSERT_EQ(player.last_report().tick, t);
    // Snapshots are built for the logged clients (exact interest by default).
    const match::Outbox& out = player.outbox();
    ASSERT_EQ(out.snapshot_count, player.match().client_count()) << "tick " << t;
    for (std::size_t i = 0; i < out.snapshot_count; ++i) ASSERT_EQ(out.snapshots[i].tick, t);
    max_snapshots = std::max(max_snapshots, out.snapshot_count);
    if (t == 2) {
      EXPECT_EQ(out.join_replies.size(), 1u);  // the first join's reply
    }
  }
  EXPECT_EQ(max_snapshots, 6u);
  EXPECT_FALSE(player.step());  // at the end nothing changes
  EXPECT_EQ(player.tick(), 200u);
}

TEST(LogPlayer, SeeksForwardAndBackwardToTheSameStateAsStepping) {
  const auto& p = played();
  const auto path = recorded_log();
  LogPlayer seeker(path.string());
  LogPlayer stepper(path.string());

  SeekResult r = seeker.seek(150);
  EXPECT_EQ(r.tick, 150u);
  EXPECT_EQ(r.ticks_simulated, 150u);
  EXPECT_EQ(r.hash_mismatches, 0u);
  EXPECT_EQ(seeker.tick(), 150u);
  EXPECT_EQ(seeker.match().state_hash(), p.ticks[149].state_hash);

  r = seeker.seek(70);  // backwards
  EXPECT_EQ(r.tick, 70u);
  EXPECT_EQ(seeker.match().state_hash(), p.ticks[69].state_hash);
  EXPECT_EQ(seeker.match().tick_index(), 70u);

  r = seeker.seek(75);  // a short step forward continues from where it is
  EXPECT_EQ(r.ticks_simulated, 5u);
  EXPECT_EQ(r.keyframe_tick, 0u);
  EXPECT_EQ(seeker.match().state_hash(), p.ticks[74].state_hash);

  // The next tick after a seek produces exactly what a player that stepped there produces.
  stepper.seek(75);
  ASSERT_TRUE(seeker.step());
  ASSERT_TRUE(stepper.step());
  EXPECT_TRUE(seeker.last_hash_matched());
  test::expect_same_snapshots(seeker.outbox(), stepper.outbox());
  EXPECT_EQ(seeker.match().clients().size(), stepper.match().clients().size());

  // Clamped to the log.
  r = seeker.seek(100000);
  EXPECT_EQ(r.tick, 200u);
  EXPECT_EQ(seeker.match().state_hash(), p.ticks[199].state_hash);
  r = seeker.seek(0);
  EXPECT_EQ(r.tick, 0u);
  EXPECT_EQ(seeker.match().tick_index(), 0u);
  EXPECT_EQ(seeker.match().client_count(), 0u);
  ASSERT_TRUE(seeker.step());
  EXPECT_EQ(seeker.match().state_hash(), p.ticks[0].state_hash);
}

TEST(LogPlayer, ReportsTamperedHashes) {
  const auto& p = played();
  const auto path = test::test_dir() / "tampered.tlog";
  test::write_played(path, p.ticks, test::match_header(), {}, 57);
  LogPlayer player(path.string());
  const SeekResult r = player.seek(100);
  EXPECT_EQ(r.hash_mismatches, 1u);
  EXPECT_EQ(r.first_mismatch_tick, 57u);
  EXPECT_TRUE(player.last_hash_matched());  // tick 100 itself matches
  player.seek(56);
  ASSERT_TRUE(player.step());
  EXPECT_FALSE(player.last_hash_matched());
  EXPECT_EQ(player.match().state_hash(), p.ticks[56].state_hash);  // the world is right, the log's hash is not
}

TEST(LogPlayer, StopsAtATornTail) {
  const auto dir = test::test_dir();
  test::write_played(dir / "full.tlog", played().ticks, test::match_header());
  const auto bytes = test::read_bytes(dir / "full.tlog");
  test::write_bytes(dir / "torn.tlog", bytes, bytes.size() / 2);
  LogPlayer player((dir / "torn.tlog").string());
  ASSERT_EQ(player.scan().end, LogEnd::torn);
  EXPECT_EQ(player.last_tick(), player.scan().last_tick);
  EXPECT_GT(player.last_tick(), 50u);
  EXPECT_LT(player.last_tick(), 200u);
  const SeekResult r = player.seek(199);
  EXPECT_EQ(r.tick, player.last_tick());
  EXPECT_EQ(r.hash_mismatches, 0u);
  EXPECT_FALSE(player.step());
}

TEST(LogPlayer, StopsBeforeAWriterGap) {
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
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  w.close();
  ASSERT_GT(w.stats().ticks_dropped, 0u);
  LogPlayer player(path.string());
  ASSERT_FALSE(player.scan().gaps.empty());
  const std::uint64_t first_missing = player.scan().gaps.front().first_tick;
  EXPECT_EQ(player.last_tick(), first_missing - 1);
  EXPECT_GT(player.scan().last_tick, first_missing);  // readable beyond, but not re-simulatable
  EXPECT_EQ(player.seek(200).tick, first_missing - 1);
  EXPECT_FALSE(player.step());
}

TEST(LogPlayer, BadFileThrowsTheReadersError) {
  const auto path = test::test_dir() / "not_a_log.tlog";
  test::write_bytes(path, {'h', 'e', 'l', 'l', 'o', '\n'}, 6);
  try {
    LogPlayer player(path.string());
    FAIL() << "no error";
  } catch (const LogError& e) {
    EXPECT_NE(std::string(e.what()).find("not a Throng match log"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace throng::matchlog
