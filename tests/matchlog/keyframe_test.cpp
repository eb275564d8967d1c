// World keyframes (format version 2): the writer places them deterministically, never waits for
// them (drops when behind, counted), the reader finds them and treats a torn or flipped keyframe
// like any other record; LogPlayer seeks through them; verify compares them, runs keyframe-aligned
// segments in parallel and names the objects that diverged.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "matchlog/checkpoint_v1.h"
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
  EXPECT_EQ(s.format_version, kFormatVersion);
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
  // Wait for the writer's first look (it finds nothing and sleeps for poll_ms), however loaded the
  // machine: only then is every keyframe below appended while it sleeps.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (w.stats().writer_sleeps == 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  ASSERT_GE(w.stats().writer_sleeps, 1u) << "the writer thread never went idle";
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
  EXPECT_EQ(r.logged_hash, p.ticks[149].state_hash);
  EXPECT_EQ(seeker.match().tick_index(), 150u);

  r = seeker.seek(120);  // onto a keyframe: restored, nothing simulated, the logged hash still known
  EXPECT_EQ(r.keyframe_tick, 120u);
  EXPECT_EQ(r.ticks_simulated, 0u);
  EXPECT_EQ(r.logged_hash, p.ticks[119].state_hash);
  EXPECT_EQ(seeker.match().state_hash(), p.ticks[119].state_hash);
  ASSERT_TRUE(seeker.step());  // and steps on from the keyframe's next tick
  EXPECT_TRUE(seeker.last_hash_matched());
  EXPECT_EQ(seeker.match().state_hash(), p.ticks[120].state_hash);

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
  EXPECT_EQ(r.logged_hash, p.ticks[29].state_hash);
  EXPECT_EQ(seeker.match().state_hash(), p.ticks[29].state_hash);
  EXPECT_EQ(seeker.seek(0).logged_hash, 0u);  // the match before its first tick

  // After a jump through a keyframe the next ticks' outbox (snapshots, replies) equals a stepped player's.
  seeker.seek(120);
  stepper.seek(120);
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(seeker.step());
    ASSERT_TRUE(stepper.step());
    EXPECT_TRUE(seeker.last_hash_matched());
    ASSERT_GT(seeker.outbox().snapshot_count, 0u);
    test::expect_same_snapshots(seeker.outbox(), stepper.outbox());
  }
}

TEST(Keyframes, PlayerWithViewerSettingsStillUsesKeyframes) {
  PlayerOptions o;
  o.resim.exact_interest = false;  // keyframes restore without their snapshot baselines
  LogPlayer player(keyframed_log().string(), o);
  const SeekResult r = player.seek(185);
  EXPECT_EQ(r.keyframe_tick, 180u);
  EXPECT_TRUE(player.keyframe_problem().empty()) << player.keyframe_problem();
  EXPECT_EQ(player.match().state_hash(), played().ticks[184].state_hash);
}

using Bytes = std::vector<std::uint8_t>;

Bytes checkpoint_of(const match::Match& m) {
  Bytes b;
  m.save_checkpoint(b);
  return b;
}

// Everything of a checkpoint but the snapshot baselines: the world and the match section
// (clients, NPC AI, facing, counters, match info).
void expect_same_state_but_baselines(const Bytes& a, const Bytes& b, const std::string& where) {
  const match::CheckpointSections x = match::checkpoint_sections(a), y = match::checkpoint_sections(b);
  EXPECT_EQ(x.tick, y.tick) << where;
  EXPECT_TRUE(std::equal(x.world.begin(), x.world.end(), y.world.begin(), y.world.end())) << where << ": world";
  EXPECT_TRUE(std::equal(x.match_state.begin(), x.match_state.end(), y.match_state.begin(), y.match_state.end()))
      << where << ": match section";
}

TEST(Keyframes, WorldOnlyRestoreThenSteppingGivesTheLoggedHashes) {
  // A fast re-simulation (1 cm interest radius, one snapshot thread) restores each logged keyframe
  // without its snapshot baselines: every later hash is the logged one, and at every 15th tick the
  // world and match state equal the live match's checkpoint; only the baselines are its own.
  const auto& p = played();
  MatchLogReader reader(keyframed_log().string());
  ASSERT_EQ(reader.scan().keyframes.size(), 3u);
  for (const KeyframeInfo& k : reader.scan().keyframes) {
    SCOPED_TRACE("from the keyframe of tick " + std::to_string(k.tick));
    Bytes logged;
    reader.read_keyframe(k, logged);
    ASSERT_TRUE(Resimulator::restores_with_fast_interest(logged));
    Resimulator sim(reader.header(), ResimOptions{});
    ASSERT_FALSE(sim.options().exact_interest);
    sim.restore(logged);
    EXPECT_EQ(sim.tick(), k.tick);
    for (std::uint64_t t = k.tick + 1; t <= p.ticks.size(); ++t) {
      TickRecord rec = p.ticks[t - 1];
      ASSERT_EQ(sim.step(rec), p.ticks[t - 1].state_hash) << "tick " << t;
      if (t % 15 == 0) {
        const Bytes mine = checkpoint_of(sim.match());
        expect_same_state_but_baselines(mine, p.keyframes[t / 15 - 1], "tick " + std::to_string(t));
        EXPECT_FALSE(match::checkpoint_sections(mine).snapshot_baselines.empty());
      }
      // The outbox still has a (tiny) snapshot per connected client, and the same replies/events.
      EXPECT_EQ(sim.outbox().snapshot_count, sim.match().client_count());
    }
  }
}

TEST(Keyframes, ViewerSeekEqualsSteppingFromTheStart) {
  // What throng-view --log and throng-replay seek see at a seek's target (world, facing, clients,
  // match info, hash) and over the next ticks (hashes, replies, client events) equals stepping
  // from tick 1, forwards and backwards, through keyframes and without.
  const auto& p = played();
  const auto path = keyframed_log();
  PlayerOptions o;
  o.resim.exact_interest = false;
  LogPlayer seeker(path.string(), o);
  for (std::uint64_t target : {150u, 70u, 185u, 60u, 121u, 20u, 199u}) {
    SCOPED_TRACE("seek to " + std::to_string(target));
    const SeekResult r = seeker.seek(target);
    ASSERT_EQ(r.tick, target);
    EXPECT_EQ(r.hash_mismatches, 0u);
    EXPECT_EQ(r.keyframe_tick, target >= 60 ? target / 60 * 60 : 0u);
    LogPlayer stepper(path.string(), o);  // only step(): never touches a keyframe
    while (stepper.tick() < target) ASSERT_TRUE(stepper.step());
    EXPECT_EQ(seeker.match().state_hash(), p.ticks[target - 1].state_hash);
    expect_same_state_but_baselines(checkpoint_of(seeker.match()), checkpoint_of(stepper.match()), "at the target");
    EXPECT_EQ(seeker.match().match_info().state, stepper.match().match_info().state);
    EXPECT_EQ(seeker.match().match_info().param_version, stepper.match().match_info().param_version);
    const auto a = seeker.match().clients(), b = stepper.match().clients();
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].client_id, b[i].client_id);
      EXPECT_EQ(a[i].entity, b[i].entity);
      EXPECT_EQ(a[i].last_applied_sequence, b[i].last_applied_sequence);
    }
    for (int i = 0; i < 3 && seeker.tick() < seeker.last_tick(); ++i) {
      ASSERT_TRUE(seeker.step());
      ASSERT_TRUE(stepper.step());
      EXPECT_TRUE(seeker.last_hash_matched());
      EXPECT_EQ(seeker.last_report().state_hash, stepper.last_report().state_hash);
      EXPECT_EQ(seeker.outbox().join_replies.size(), stepper.outbox().join_replies.size());
      EXPECT_EQ(seeker.outbox().param_replies.size(), stepper.outbox().param_replies.size());
      EXPECT_EQ(seeker.outbox().client_events.size(), stepper.outbox().client_events.size());
      EXPECT_EQ(seeker.outbox().match_info_changed, stepper.outbox().match_info_changed);
    }
  }
}

TEST(Keyframes, PlaySeekKeepsTheServersSnapshotsByteForByte) {
  // The default player (play): after a seek through a keyframe, the whole match state, snapshot
  // baselines included, equals stepping from tick 1, and so do the next ticks' snapshots.
  const auto path = keyframed_log();
  LogPlayer seeker(path.string());
  LogPlayer stepper(path.string());
  const SeekResult r = seeker.seek(133);
  ASSERT_EQ(r.keyframe_tick, 120u);
  while (stepper.tick() < 133) ASSERT_TRUE(stepper.step());
  EXPECT_EQ(checkpoint_of(seeker.match()), checkpoint_of(stepper.match()));
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(seeker.step());
    ASSERT_TRUE(stepper.step());
    ASSERT_GT(seeker.outbox().snapshot_count, 0u);
    test::expect_same_snapshots(seeker.outbox(), stepper.outbox());
  }
}

TEST(Keyframes, KeyframesWithoutBaselinesSeekVerifyAndSaySo) {
  // The server's default keyframes (no snapshot baselines): smaller, the header says so, verify
  // passes in both interest modes without a note, and play's seek reaches exactly the stepped
  // world and match state; only its snapshot baselines start afresh at the keyframe.
  const auto& p = played();
  const auto full_path = keyframed_log("kf-full.tlog");  // test_dir() empties the folder: once
  const auto path = full_path.parent_path() / "kf-lean.tlog";
  test::write_played(path, p.ticks, test::match_header(), {}, 0, &p.lean_keyframes);
  MatchLogReader full(full_path.string()), reader(path.string());
  EXPECT_TRUE(full.header().writer.keyframe_snapshot_baselines);
  EXPECT_FALSE(reader.header().writer.keyframe_snapshot_baselines);
  ASSERT_EQ(reader.scan().keyframes.size(), 3u);
  EXPECT_LT(reader.scan().keyframe_raw_bytes, full.scan().keyframe_raw_bytes);
  for (bool exact : {true, false}) {
    for (unsigned jobs : {1u, 2u}) {
      SCOPED_TRACE(fmt::format("exact {} jobs {}", exact, jobs));
      ResimOptions o;
      o.exact_interest = exact;
      const VerifyResult v = verify_log(reader, {}, 30, o, jobs);
      EXPECT_TRUE(v.all_match()) << v.diff_note;
      EXPECT_TRUE(v.keyframe_note.empty()) << v.keyframe_note;
      EXPECT_EQ(v.keyframes_checked, 3u);
    }
  }
  LogPlayer seeker(path.string());  // play's settings
  LogPlayer stepper(path.string());
  const SeekResult r = seeker.seek(133);
  ASSERT_EQ(r.keyframe_tick, 120u);
  EXPECT_EQ(r.hash_mismatches, 0u);
  while (stepper.tick() < 133) ASSERT_TRUE(stepper.step());
  const Bytes a = checkpoint_of(seeker.match()), b = checkpoint_of(stepper.match());
  const match::CheckpointSections sa = match::checkpoint_sections(a), sb = match::checkpoint_sections(b);
  EXPECT_TRUE(std::equal(sa.world.begin(), sa.world.end(), sb.world.begin(), sb.world.end()));
  EXPECT_TRUE(std::equal(sa.match_state.begin(), sa.match_state.end(), sb.match_state.begin(), sb.match_state.end()));
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(seeker.step());
    ASSERT_TRUE(stepper.step());
    EXPECT_EQ(seeker.match().state_hash(), stepper.match().state_hash());
    ASSERT_EQ(seeker.outbox().snapshot_count, stepper.outbox().snapshot_count);  // every client still served
  }
}

TEST(Keyframes, HeaderSaysWhetherKeyframesHoldBaselinesAndOlderHeadersDid) {
  LogHeader h = test::match_header();
  h.writer.keyframe_snapshot_baselines = false;
  const std::string text = header_to_json_text(h);
  EXPECT_FALSE(header_from_json_text(text).writer.keyframe_snapshot_baselines);
  nlohmann::json j = nlohmann::json::parse(text);
  j["writer"].erase("keyframe_snapshot_baselines");  // written before keyframes could leave them out
  EXPECT_TRUE(header_from_json_text(j.dump()).writer.keyframe_snapshot_baselines);
  j["writer"]["keyframe_snapshot_baselines"] = 1;
  EXPECT_THROW(header_from_json_text(j.dump()), LogError);
}

TEST(Keyframes, VersionOneKeyframesOfEarlierBuildsStillSeekAndVerify) {
  // An earlier build's log: its keyframes are checkpoint version 1, which restore only into the
  // logged interest settings. The viewer's player switches to them at its first restore; verify
  // runs such segments with them; both still use the keyframes.
  const auto& p = played();
  std::vector<Bytes> v1;
  const LogHeader h = test::match_header();
  for (const Bytes& k : p.keyframes) v1.push_back(::throng::test::as_version_1(::throng::test::as_version_3(k, h.scene, h.config), h.config));
  const auto path = test::test_dir() / "v1kf.tlog";
  test::write_played(path, p.ticks, test::match_header(), {}, 0, &v1);
  PlayerOptions o;
  o.resim.exact_interest = false;
  LogPlayer player(path.string(), o);
  const SeekResult r = player.seek(150);
  EXPECT_EQ(r.keyframe_tick, 120u);
  EXPECT_TRUE(player.keyframe_problem().empty()) << player.keyframe_problem();
  EXPECT_EQ(player.match().state_hash(), p.ticks[149].state_hash);
  EXPECT_EQ(r.hash_mismatches, 0u);
  MatchLogReader reader(path.string());
  Bytes k;
  reader.read_keyframe(reader.scan().keyframes[0], k);
  EXPECT_FALSE(Resimulator::restores_with_fast_interest(k));
  for (unsigned jobs : {1u, 2u}) {
    const VerifyResult v = verify_log(reader, {}, 30, {}, jobs);
    EXPECT_TRUE(v.all_match()) << jobs << " " << v.diff_note << " " << v.keyframe_note;
    EXPECT_EQ(v.keyframes_checked, 3u);
  }
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
