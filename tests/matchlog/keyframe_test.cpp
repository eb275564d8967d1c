// World keyframes (format version 2): the writer places them deterministically, never waits for
// them (drops when behind, counted), the reader finds them and treats a torn or flipped keyframe
// like any other record; LogPlayer seeks through them; verify compares them, runs keyframe-aligned
// segments in parallel and names the objects that diverged.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "matchlog_test_util.h"
#include "throng/match/checkpoint_diff.h"
#include "throng/matchlog/log_player.h"
#include "throng/matchlog/reader.h"
#include "throng/matchlog/replay.h"

namespace throng::matchlog {
namespace {

const test::PlayedMatch& played() {
  static const test::PlayedMatch p = test::play_match(200);
  return p;
}

// The played match with a keyframe every 60 ticks (60, 120, 180).
std::filesystem::path keyframed_log(const std::string& name = "kf.tlog", std::uint64_t tamper_tick = 0) {
  const auto path = test::test_dir() / name;
  test::write_played(path, played().ticks, test::match_header(), {}, tamper_tick, &played().keyframes);
  return path;
}

TEST(Keyframes, WrittenAfterTheirTickAndIndexed) {
  const auto path = keyframed_log();
  MatchLogReader r(path.string());
  const LogScan& s = r.scan();
  ASSERT_EQ(s.end, LogEnd::closed) << s.problem;
  EXPECT_EQ(s.format_version, 2u);
  EXPECT_EQ(r.header().writer.keyframe_interval_ticks, 60u);
  ASSERT_EQ(s.keyframes.size(), 3u);
  std::vector<std::uint8_t> bytes;
  for (std::size_t i = 0; i < 3; ++i) {
    const KeyframeInfo& k = s.keyframes[i];
    EXPECT_EQ(k.tick, 60u * (i + 1));
    // Right after the block ending at its tick.
    const BlockInfo* b = r.find_block(k.tick);
    ASSERT_NE(b, nullptr);
    EXPECT_EQ(b->first_tick + b->tick_count - 1, k.tick);
    EXPECT_EQ(k.offset, b->offset + b->record_bytes);
    r.read_keyframe(k, bytes);
    EXPECT_EQ(bytes, played().keyframes[k.tick / 15 - 1]) << "tick " << k.tick;
    EXPECT_EQ(k.raw_size, bytes.size());
    EXPECT_LT(k.record_bytes, k.raw_size);  // zstd
  }
  EXPECT_GT(s.keyframe_bytes, 0u);
  // Nearest keyframe at or before a tick.
  EXPECT_EQ(r.find_keyframe(59), nullptr);
  EXPECT_EQ(r.find_keyframe(60)->tick, 60u);
  EXPECT_EQ(r.find_keyframe(179)->tick, 120u);
  EXPECT_EQ(r.find_keyframe(100000)->tick, 180u);
  // Ticks still read as before.
  TickRecord t;
  std::uint64_t n = 0;
  while (r.next(t)) ASSERT_EQ(t.state_hash, played().ticks[n++].state_hash);
  EXPECT_EQ(n, 200u);
}

TEST(Keyframes, SameInputsSameFileApartFromTheHeaderTime) {
  const auto dir = test::test_dir();
  test::write_played(dir / "a.tlog", played().ticks, test::match_header(), {}, 0, &played().keyframes);
  WriterOptions slow;
  slow.poll_ms = 1;  // the writer thread races the appends: placement must not depend on timing
  test::write_played(dir / "b.tlog", played().ticks, test::match_header(), slow, 0, &played().keyframes);
  const auto a = test::read_bytes(dir / "a.tlog"), b = test::read_bytes(dir / "b.tlog");
  ASSERT_EQ(a.size(), b.size());
  const std::size_t header = MatchLogReader((dir / "a.tlog").string()).scan().header_bytes;
  EXPECT_TRUE(std::equal(a.begin() + static_cast<std::ptrdiff_t>(header), a.end(), b.begin() + static_cast<std::ptrdiff_t>(header)));
}

TEST(Keyframes, AppendKeyframeChecksItsTick) {
  const auto dir = test::test_dir();
  MatchLogWriter w((dir / "x.tlog").string());
  w.begin(test::match_header());
  const std::vector<std::uint8_t> bytes(100, 7);
  for (std::uint64_t t = 1; t <= 60; ++t) w.append_tick(t, {}, t);
  EXPECT_THROW(w.append_keyframe(59, bytes), std::invalid_argument);  // not the last appended tick
  w.append_keyframe(60, bytes);
  w.append_tick(61, {}, 61);
  EXPECT_THROW(w.append_keyframe(61, bytes), std::invalid_argument);  // not on the interval
  w.close();
  EXPECT_EQ(w.stats().keyframes_written, 1u);

  WriterOptions off;
  off.keyframe_interval_ticks = 0;
  MatchLogWriter none((dir / "y.tlog").string(), off);
  none.begin(test::match_header());
  none.append_tick(1, {}, 1);
  EXPECT_THROW(none.append_keyframe(1, bytes), std::invalid_argument);
  none.close();
  MatchLogReader r((dir / "y.tlog").string());
  EXPECT_TRUE(r.scan().keyframes.empty());
  EXPECT_EQ(r.header().writer.keyframe_interval_ticks, 0u);
}

TEST(Keyframes, WriterBehindDropsKeyframesLoudlyNotTicks) {
  const auto path = test::test_dir() / "behind.tlog";
  WriterOptions o;
  o.keyframe_slots = 1;
  o.poll_ms = 3000;  // the writer thread sleeps through the whole match (close() wakes it)
  MatchLogWriter w(path.string(), o);
  w.begin(test::match_header());
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // its first look found nothing; now it sleeps
  const auto& p = played();
  for (const TickRecord& t : p.ticks) {
    w.append_tick(t.tick, t.inputs, t.state_hash, t.flags);
    if (t.tick % 60 == 0) w.append_keyframe(t.tick, p.keyframes[t.tick / 15 - 1]);
  }
  const WriterStats before = w.stats();
  EXPECT_EQ(before.keyframes_appended, 3u);
  EXPECT_EQ(before.keyframes_dropped, 2u);  // 120 and 180: the one slot still held 60
  w.close();
  const WriterStats s = w.stats();
  EXPECT_EQ(s.keyframes_written, 1u);
  EXPECT_EQ(s.ticks_written, 200u);
  EXPECT_EQ(s.ticks_dropped, 0u);
  MatchLogReader r(path.string());
  ASSERT_EQ(r.scan().end, LogEnd::closed) << r.scan().problem;
  ASSERT_EQ(r.scan().keyframes.size(), 1u);
  EXPECT_EQ(r.scan().keyframes[0].tick, 60u);
  EXPECT_TRUE(verify_log(r).all_match());
}

TEST(Keyframes, TornKeyframeIsATornTail) {
  const auto dir = test::test_dir();
  const auto full = keyframed_log();
  const auto bytes = test::read_bytes(full);
  MatchLogReader whole(full.string());
  const KeyframeInfo k = whole.scan().keyframes[1];  // tick 120
  const auto torn = dir / "torn.tlog";
  // Cut anywhere inside the keyframe record: every tick up to 120 is kept, the keyframe is not.
  for (std::uint64_t cut = k.offset + 1; cut < k.offset + k.record_bytes; cut += std::max<std::uint64_t>(1, k.record_bytes / 37)) {
    test::write_bytes(torn, bytes, cut);
    MatchLogReader r(torn.string());
    ASSERT_EQ(r.scan().end, LogEnd::torn) << "cut at " << cut << ": " << r.scan().problem;
    EXPECT_EQ(r.scan().last_tick, 120u);
    EXPECT_EQ(r.scan().damage_offset, k.offset);
    ASSERT_EQ(r.scan().keyframes.size(), 1u);
    EXPECT_NE(r.scan().problem.find("after tick 120"), std::string::npos) << r.scan().problem;
  }
  // Cut exactly after it: unclosed, both keyframes kept, and a player seeks through them.
  test::write_bytes(torn, bytes, k.offset + k.record_bytes);
  LogPlayer player(torn.string());
  EXPECT_EQ(player.scan().end, LogEnd::unclosed);
  EXPECT_EQ(player.scan().keyframes.size(), 2u);
  const SeekResult s = player.seek(200);
  EXPECT_EQ(s.tick, 120u);
  EXPECT_EQ(s.keyframe_tick, 120u);
  EXPECT_EQ(player.match().state_hash(), played().ticks[119].state_hash);
}

TEST(Keyframes, FlippedByteInAKeyframeIsCorruptionAtThatRecord) {
  const auto dir = test::test_dir();
  auto bytes = test::read_bytes(keyframed_log());
  const KeyframeInfo k = MatchLogReader((dir / "kf.tlog").string()).scan().keyframes[0];
  bytes[k.offset + k.record_bytes / 2] ^= 0x10;
  const auto bad = dir / "flipped.tlog";
  test::write_bytes(bad, bytes, bytes.size());
  MatchLogReader r(bad.string());
  EXPECT_EQ(r.scan().end, LogEnd::corrupt);
  EXPECT_EQ(r.scan().damage_offset, k.offset);
  EXPECT_EQ(r.scan().last_tick, 60u);
  EXPECT_NE(r.scan().problem.find("corrupt record at byte " + std::to_string(k.offset)), std::string::npos) << r.scan().problem;
}

TEST(Keyframes, PlayerSeeksThroughTheNearestKeyframe) {
  const auto& p = played();
  const auto path = keyframed_log();
  LogPlayer seeker(path.string());
  LogPlayer stepper(path.string());
  ASSERT_TRUE(seeker.keyframe_problem().empty());

  SeekResult r = seeker.seek(150);
  EXPECT_TRUE(seeker.keyframe_problem().empty()) << seeker.keyframe_problem();
  EXPECT_EQ(r.keyframe_tick, 120u);
  EXPECT_EQ(r.ticks_simulated, 30u);
  EXPECT_EQ(r.hash_mismatches, 0u);
  EXPECT_EQ(seeker.match().state_hash(), p.ticks[149].state_hash);
  EXPECT_EQ(seeker.match().tick_index(), 150u);

  r = seeker.seek(70);  // backwards
  EXPECT_EQ(r.keyframe_tick, 60u);
  EXPECT_EQ(r.ticks_simulated, 10u);
  EXPECT_EQ(seeker.match().state_hash(), p.ticks[69].state_hash);

  r = seeker.seek(80);  // forwards with no keyframe in between: steps on
  EXPECT_EQ(r.keyframe_tick, 0u);
  EXPECT_EQ(r.ticks_simulated, 10u);

  r = seeker.seek(30);  // before the first keyframe: from the match start
  EXPECT_EQ(r.keyframe_tick, 0u);
  EXPECT_EQ(r.ticks_simulated, 30u);
  EXPECT_EQ(seeker.match().state_hash(), p.ticks[29].state_hash);

  // After a jump through a keyframe the next ticks' outbox (snapshots, replies) equals a stepped player's.
  seeker.seek(120);
  stepper.seek(120);
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(seeker.step());
    ASSERT_TRUE(stepper.step());
    EXPECT_TRUE(seeker.last_hash_matched());
    const match::Outbox &a = seeker.outbox(), &b = stepper.outbox();
    ASSERT_EQ(a.snapshot_count, b.snapshot_count);
    ASSERT_GT(a.snapshot_count, 0u);
    for (std::size_t s = 0; s < a.snapshot_count; ++s) {
      EXPECT_EQ(a.snapshots[s].client_id, b.snapshots[s].client_id);
      EXPECT_EQ(a.snapshots[s].id_codes, b.snapshots[s].id_codes);
      EXPECT_EQ(a.snapshots[s].x, b.snapshots[s].x);
      EXPECT_EQ(a.snapshots[s].yaw, b.snapshots[s].yaw);
      EXPECT_EQ(a.snapshots[s].removed, b.snapshots[s].removed);
    }
  }
}

TEST(Keyframes, PlayerWithViewerSettingsStillUsesKeyframes) {
  PlayerOptions o;
  o.resim.exact_interest = false;  // a log with keyframes overrides this (checkpoints need the logged config)
  LogPlayer player(keyframed_log().string(), o);
  const SeekResult r = player.seek(185);
  EXPECT_EQ(r.keyframe_tick, 180u);
  EXPECT_EQ(player.match().state_hash(), played().ticks[184].state_hash);
}

TEST(Keyframes, VerifyComparesKeyframesAndSplitsIntoSegments) {
  MatchLogReader r(keyframed_log().string());
  const VerifyResult one = verify_log(r);
  EXPECT_TRUE(one.all_match());
  EXPECT_EQ(one.ticks_verified, 200u);
  EXPECT_EQ(one.keyframes_checked, 3u);
  EXPECT_EQ(one.segments, 1u);
  for (unsigned jobs : {2u, 3u, 8u}) {
    std::uint64_t last_done = 0;
    const VerifyResult v = verify_log(r, [&](std::uint64_t done, std::uint64_t) { last_done = done; }, 30, {}, jobs);
    EXPECT_TRUE(v.all_match()) << jobs;
    EXPECT_EQ(v.ticks_verified, 200u);
    EXPECT_EQ(v.segments, 4u);  // from 0, 60, 120, 180
    EXPECT_EQ(v.jobs, std::min(jobs, 4u));
    EXPECT_EQ(v.keyframes_checked, 3u);  // each segment's first checked hash proves its restore
    EXPECT_EQ(last_done, 200u);
  }
}

TEST(Keyframes, VerifyNamesTheObjectsThatDiverged) {
  // One command lost at tick 70: the re-simulation diverges there; from the keyframe of tick 60 to
  // the keyframe of tick 120 the re-simulated world differs from the logged one in named objects.
  auto ticks = played().ticks;
  std::uint32_t moved_entity = 0;
  for (auto& t : ticks) {
    if (t.tick >= 70 && !t.inputs.commands.empty()) {
      moved_entity = t.inputs.commands.front().entity;
      t.inputs.commands.erase(t.inputs.commands.begin());
      break;
    }
  }
  const auto path = test::test_dir() / "lost.tlog";
  test::write_played(path, ticks, test::match_header(), {}, 0, &played().keyframes);
  MatchLogReader r(path.string());
  for (unsigned jobs : {1u, 2u}) {
    const VerifyResult v = verify_log(r, {}, 30, {}, jobs);
    ASSERT_TRUE(v.mismatch) << jobs;
    EXPECT_GE(v.mismatch_tick, 70u);
    EXPECT_LT(v.mismatch_tick, 120u);
    EXPECT_EQ(v.ticks_verified, v.mismatch_tick - 1);
    EXPECT_EQ(v.diff_from_tick, 60u);
    EXPECT_EQ(v.diff_tick, 120u);
    ASSERT_FALSE(v.differences.empty()) << v.diff_note;
    EXPECT_LE(v.differences.size(), 20u);
    // Ascending ids, each saying what differs.
    for (std::size_t i = 1; i < v.differences.size(); ++i) EXPECT_LT(v.differences[i - 1].object_id, v.differences[i].object_id);
    EXPECT_FALSE(v.differences.front().what.empty());
  }
  (void)moved_entity;
}

TEST(Keyframes, TamperedHashWithAnIntactWorldIsSaidSo) {
  MatchLogReader r(keyframed_log("t.tlog", 57).string());
  const VerifyResult v = verify_log(r);
  ASSERT_TRUE(v.mismatch);
  EXPECT_EQ(v.mismatch_tick, 57u);
  EXPECT_TRUE(v.differences.empty());
  EXPECT_EQ(v.diff_tick, 60u);
  EXPECT_NE(v.diff_note.find("logged state hash itself looks wrong"), std::string::npos) << v.diff_note;
}

TEST(Keyframes, AWrongKeyframeIsAKeyframeMismatch) {
  // The keyframe logged for tick 120 holds the world of tick 105: every hash matches, the
  // checkpoint comparison does not.
  auto kf = played().keyframes;
  kf[120 / 15 - 1] = kf[105 / 15 - 1];
  const auto path = test::test_dir() / "wrong_kf.tlog";
  test::write_played(path, played().ticks, test::match_header(), {}, 0, &kf);
  MatchLogReader r(path.string());
  const VerifyResult v = verify_log(r);
  EXPECT_FALSE(v.mismatch);
  ASSERT_TRUE(v.keyframe_mismatch);
  EXPECT_EQ(v.keyframe_mismatch_tick, 120u);
  EXPECT_EQ(v.ticks_verified, 120u);
  EXPECT_FALSE(v.differences.empty());  // bodies moved between 105 and 120
  EXPECT_FALSE(v.all_match());
}

TEST(Keyframes, VersionOneLogsStillRead) {
  // A v1 file: this build's writer output with keyframes off, the preamble/header version set to 1
  // and the index records rewritten without their keyframe part is what v1 wrote; simplest honest
  // check: a v2 log without keyframes has no keyframe records, and v1 refuses keyframe records.
  const auto path = test::test_dir() / "nokf.tlog";
  test::write_played(path, played().ticks, test::match_header());
  MatchLogReader r(path.string());
  EXPECT_TRUE(r.scan().keyframes.empty());
  const VerifyResult v = verify_log(r, {}, 30, {}, 4);
  EXPECT_TRUE(v.all_match());
  EXPECT_EQ(v.segments, 1u);  // nothing to split on
  EXPECT_EQ(v.keyframes_checked, 0u);
  LogPlayer player(path.string());
  EXPECT_EQ(player.seek(150).keyframe_tick, 0u);
}

}  // namespace
}  // namespace throng::matchlog
