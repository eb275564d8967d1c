// MatchFollower (follower.h): a match kept in step with a primary from its tick entries and
// checkpoints, checked against a recorded match (play_match: joins, commands good and bad, operator
// changes, a leave, a shutdown).
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "matchlog_test_util.h"
#include "throng/matchlog/follower.h"
#include "throng/matchlog/format.h"
#include "throng/matchlog/log_player.h"
#include "throng/matchlog/reader.h"
#include "throng/matchlog/replay.h"
#include "throng/matchlog/writer.h"
#include "throng/world/world.h"

namespace throng::matchlog {
namespace {
using namespace test;

std::vector<std::uint8_t> entry_of(const TickRecord& t) {
  std::vector<std::uint8_t> bytes;
  encode_tick(t.tick, t.inputs, t.state_hash, t.flags, bytes);
  return bytes;
}

const PlayedMatch& played() {
  static const PlayedMatch p = play_match(150);
  return p;
}

// The checkpoint saved after tick t (t a multiple of 15), with snapshot baselines.
std::span<const std::uint8_t> checkpoint_after(std::uint64_t t) { return played().keyframes.at(t / 15 - 1); }

void feed(MatchFollower& f, std::uint64_t from, std::uint64_t to) {
  for (std::uint64_t t = from; t <= to; ++t) f.on_tick_entry(entry_of(played().ticks.at(t - 1)));
}

TEST(MatchFollower, StartedWithThePrimaryFollowsEveryTickWithoutACheckpoint) {
  MatchFollower f(match_header());
  EXPECT_EQ(f.state(), FollowState::following);
  for (std::uint64_t t = 1; t <= 150; ++t) {
    f.on_tick_entry(entry_of(played().ticks[t - 1]));
    ASSERT_EQ(f.tick(), t);
    ASSERT_EQ(f.match().state_hash(), played().ticks[t - 1].state_hash) << "tick " << t;
  }
  EXPECT_EQ(f.state(), FollowState::following);
  EXPECT_EQ(f.stats().applied, 150u);
  EXPECT_EQ(f.stats().mismatches, 0u);
  EXPECT_EQ(f.stats().checkpoints, 0u);
}

// A follower records no push events (nothing reads them) and still follows every tick; one told
// to keep the logged config's records them, with the same hashes.
TEST(MatchFollower, RecordsNoPushEventsUnlessAsked) {
  MatchFollower quiet(match_header());
  FollowerOptions logged_options;
  logged_options.resim.logged_push_events = true;
  MatchFollower logged(match_header(), logged_options);
  std::size_t logged_events = 0;
  for (std::uint64_t t = 1; t <= 150; ++t) {
    quiet.on_tick_entry(entry_of(played().ticks[t - 1]));
    logged.on_tick_entry(entry_of(played().ticks[t - 1]));
    ASSERT_EQ(quiet.match().state_hash(), played().ticks[t - 1].state_hash) << "tick " << t;
    ASSERT_EQ(logged.match().state_hash(), played().ticks[t - 1].state_hash) << "tick " << t;
    EXPECT_TRUE(quiet.match().world().push_events().empty()) << "tick " << t;
    logged_events += logged.match().world().push_events().size();
  }
  EXPECT_GT(logged_events, 0u);
}

TEST(MatchFollower, StartedLateAsksForACheckpointAndAppliesWhatItHeld) {
  MatchFollower f(match_header());
  feed(f, 31, 47);  // joined the stream at tick 31: nothing can be applied yet
  EXPECT_EQ(f.state(), FollowState::needs_checkpoint);
  EXPECT_EQ(f.tick(), 0u);
  EXPECT_EQ(f.held(), 17u);
  EXPECT_EQ(f.stats().gaps, 1u);
  f.on_checkpoint(checkpoint_after(30));  // the answer to its request, saved after tick 30
  EXPECT_EQ(f.state(), FollowState::following);
  EXPECT_EQ(f.tick(), 47u);
  EXPECT_EQ(f.held(), 0u);
  EXPECT_EQ(f.match().state_hash(), played().ticks[46].state_hash);
  feed(f, 48, 150);
  EXPECT_EQ(f.tick(), 150u);
  EXPECT_EQ(f.match().state_hash(), played().ticks[149].state_hash);
  EXPECT_EQ(f.stats().applied, 150u - 30u);
  EXPECT_EQ(f.stats().mismatches, 0u);
}

TEST(MatchFollower, ACheckpointAheadOfTheHeldEntriesDropsThoseItCovers) {
  MatchFollower f(match_header());
  feed(f, 20, 50);
  f.on_checkpoint(checkpoint_after(45));
  EXPECT_EQ(f.tick(), 50u);
  EXPECT_EQ(f.state(), FollowState::following);
  EXPECT_EQ(f.stats().stale_entries, 26u);  // ticks 20..45 were in the checkpoint
  EXPECT_EQ(f.stats().applied, 5u);
  EXPECT_EQ(f.match().state_hash(), played().ticks[49].state_hash);
}

TEST(MatchFollower, RepeatedAndOldEntriesChangeNothing) {
  MatchFollower f(match_header());
  feed(f, 1, 40);
  const std::uint64_t hash = f.match().state_hash();
  feed(f, 30, 40);  // a writer that resent its history
  EXPECT_EQ(f.tick(), 40u);
  EXPECT_EQ(f.match().state_hash(), hash);
  EXPECT_EQ(f.stats().stale_entries, 11u);
  EXPECT_EQ(f.state(), FollowState::following);
}

TEST(MatchFollower, AMissingTickStopsItUntilTheTickOrACheckpointComes) {
  MatchFollower f(match_header());
  feed(f, 1, 20);
  feed(f, 22, 25);  // 21 lost
  EXPECT_EQ(f.tick(), 20u);
  EXPECT_EQ(f.state(), FollowState::needs_checkpoint);
  EXPECT_EQ(f.stats().gaps, 1u);
  feed(f, 21, 21);  // it arrived after all: applied, and the held ones after it
  EXPECT_EQ(f.tick(), 25u);
  EXPECT_EQ(f.state(), FollowState::following);
  feed(f, 27, 33);  // 26 lost for good
  EXPECT_EQ(f.stats().gaps, 2u);
  EXPECT_EQ(f.tick(), 25u);
  f.on_checkpoint(checkpoint_after(30));
  EXPECT_EQ(f.tick(), 33u);
  EXPECT_EQ(f.state(), FollowState::following);
  EXPECT_EQ(f.match().state_hash(), played().ticks[32].state_hash);
}

TEST(MatchFollower, ADivergentTickIsNamedAndAFreshCheckpointResynchronises) {
  MatchFollower f(match_header());
  feed(f, 1, 39);
  // Tick 40 as a primary would have sent it had its match gone another way: the operator's weight
  // change is missing, so the recomputed state differs from the hash it carries.
  TickRecord altered = played().ticks[39];
  ASSERT_FALSE(altered.inputs.params.empty());
  const std::uint32_t changed_entity = altered.inputs.params.front().entity;
  const std::string changed_param = altered.inputs.params.front().param;
  altered.inputs.params.clear();
  f.on_tick_entry(entry_of(altered));
  EXPECT_EQ(f.tick(), 40u);
  EXPECT_EQ(f.stats().mismatches, 1u);
  EXPECT_EQ(f.stats().first_mismatch_tick, 40u);
  EXPECT_EQ(f.state(), FollowState::needs_checkpoint);
  EXPECT_NE(f.match().state_hash(), played().ticks[39].state_hash);
  feed(f, 41, 50);  // held, not applied to a match that is not the primary's
  EXPECT_EQ(f.tick(), 40u);
  EXPECT_EQ(f.held(), 10u);
  f.on_checkpoint(checkpoint_after(45));
  EXPECT_EQ(f.state(), FollowState::following);
  EXPECT_EQ(f.tick(), 50u);
  EXPECT_EQ(f.match().state_hash(), played().ticks[49].state_hash);
  EXPECT_EQ(f.stats().mismatches, 1u);
  // Before restoring, the diverged match was brought to tick 45 with the held entries and compared
  // with the checkpoint: the object whose parameter change was left out is named.
  const Divergence& d = f.last_divergence();
  EXPECT_EQ(d.first_tick, 40u);
  EXPECT_EQ(d.compared_at, 45u) << d.note;
  bool named = false;
  for (const auto& diff : d.differences)
    named = named || (diff.object_id == changed_entity && diff.what.find(changed_param) != std::string::npos);
  EXPECT_TRUE(named) << "object " << changed_entity << " (" << changed_param << ") among " << d.differences.size() << " differences";
}

TEST(MatchFollower, AnOlderCheckpointIsIgnoredWhileFollowing) {
  MatchFollower f(match_header());
  feed(f, 1, 50);
  f.on_checkpoint(checkpoint_after(30));
  EXPECT_EQ(f.tick(), 50u);
  EXPECT_EQ(f.stats().stale_checkpoints, 1u);
  EXPECT_EQ(f.stats().checkpoints, 0u);
  feed(f, 51, 60);
  EXPECT_EQ(f.match().state_hash(), played().ticks[59].state_hash);
}

TEST(MatchFollower, BadBytesAreRefusedWithNothingChanged) {
  MatchFollower f(match_header());
  feed(f, 1, 20);
  const std::vector<std::uint8_t> good = entry_of(played().ticks[20]);
  std::vector<std::uint8_t> truncated(good.begin(), good.end() - 1);
  EXPECT_THROW(f.on_tick_entry(truncated), LogError);
  std::vector<std::uint8_t> two = good;
  two.insert(two.end(), good.begin(), good.end());
  EXPECT_THROW(f.on_tick_entry(two), LogError);
  EXPECT_THROW(f.on_tick_entry(entry_of(TickRecord{})), LogError);  // tick 0
  EXPECT_THROW(f.on_tick_entry({}), LogError);
  EXPECT_EQ(f.tick(), 20u);
  EXPECT_EQ(f.held(), 0u);

  std::vector<std::uint8_t> damaged(checkpoint_after(45).begin(), checkpoint_after(45).end());
  damaged.resize(damaged.size() / 2);
  EXPECT_ANY_THROW(f.on_checkpoint(damaged));
  EXPECT_THROW(f.on_checkpoint(std::vector<std::uint8_t>{1, 2, 3}), match::CheckpointError);
  EXPECT_EQ(f.tick(), 20u);
  EXPECT_EQ(f.state(), FollowState::following);
  f.on_tick_entry(good);  // still follows
  EXPECT_EQ(f.tick(), 21u);
  EXPECT_EQ(f.match().state_hash(), played().ticks[20].state_hash);
}

TEST(MatchFollower, HoldsAtMostItsLimitKeepingTheNewest) {
  FollowerOptions o;
  o.max_held_ticks = 8;
  MatchFollower f(match_header(), o);
  feed(f, 11, 30);
  EXPECT_EQ(f.held(), 8u);
  EXPECT_EQ(f.stats().held_dropped, 12u);
  f.on_checkpoint(checkpoint_after(15));  // ticks 16..22 were dropped: still short of the held 23..30
  EXPECT_EQ(f.tick(), 15u);
  EXPECT_EQ(f.state(), FollowState::needs_checkpoint);
  f.on_checkpoint(checkpoint_after(30));
  EXPECT_EQ(f.tick(), 30u);
  EXPECT_EQ(f.state(), FollowState::following);
  EXPECT_EQ(f.held(), 0u);
}

// A standby's own log (MatchLogWriter::begin_from, FollowerOptions::on_applied): it starts from the
// checkpoint the follower started from, holds every tick the follower applied, verifies from that
// keyframe (one job and two) and seeks within it; every tick agrees with the primary's recording.
TEST(StandbyLog, StartsFromTheCheckpointVerifiesAndSeeksFromIt) {
  const std::filesystem::path path = test_dir() / "standby.tlog";
  WriterOptions wo;
  wo.keyframe_interval_ticks = 30;
  wo.keyframe_slots = 8;  // the test appends within a millisecond, a server one keyframe a second
  MatchLogWriter w(path.string(), wo);
  MatchFollower* follower = nullptr;
  std::vector<std::uint8_t> keyframe;
  FollowerOptions fo;
  fo.on_applied = [&](std::uint64_t tick, std::uint64_t hash, std::uint8_t flags, const match::TickInputs& inputs) {
    w.append_tick(tick, inputs, hash, flags);
    if (tick % w.keyframe_interval_ticks() == 0) {
      follower->match().save_checkpoint(keyframe, match::SaveOptions{.snapshot_baselines = false});
      w.append_keyframe_swap(tick, keyframe);
    }
  };
  MatchFollower f(match_header(), fo);
  follower = &f;
  feed(f, 31, 47);
  w.begin_from(match_header(), 30, std::vector<std::uint8_t>(checkpoint_after(30).begin(), checkpoint_after(30).end()));
  f.on_checkpoint(checkpoint_after(30));
  feed(f, 48, 150);
  ASSERT_EQ(f.tick(), 150u);
  w.close();

  MatchLogReader r(path.string());
  const LogScan& s = r.scan();
  EXPECT_EQ(s.first_tick, 31u);
  EXPECT_EQ(s.last_tick, 150u);
  EXPECT_EQ(s.ticks, 120u);
  EXPECT_EQ(s.end, LogEnd::closed);
  EXPECT_EQ(start_keyframe_tick(s), 30u);
  EXPECT_TRUE(holes(s).empty());
  ASSERT_EQ(s.keyframes.size(), 5u) << "the start (tick 30), then 60, 90, 120 and 150";
  TickCursor cursor(r);
  ASSERT_TRUE(cursor.seek(31));
  TickRecord t;
  for (std::uint64_t tick = 31; tick <= 150; ++tick) {
    ASSERT_TRUE(cursor.next(t));
    ASSERT_EQ(t.tick, tick);
    EXPECT_EQ(t.state_hash, played().ticks.at(tick - 1).state_hash) << "tick " << tick;
    EXPECT_EQ(t.flags, played().ticks.at(tick - 1).flags);
  }
  for (unsigned jobs : {1u, 2u}) {
    const VerifyResult v = verify_log(r, {}, 0, ResimOptions{}, jobs);
    EXPECT_TRUE(v.all_match()) << "jobs " << jobs;
    EXPECT_EQ(v.start_tick, 30u);
    EXPECT_EQ(v.ticks_verified, 120u);
    EXPECT_EQ(v.keyframes_checked, 4u) << "the keyframes of ticks 60, 90, 120 and 150";
  }

  LogPlayer p(path.string());
  EXPECT_EQ(p.first_tick(), 31u);
  EXPECT_EQ(p.last_tick(), 150u);
  EXPECT_EQ(p.seek(100).logged_hash, played().ticks.at(99).state_hash);
  EXPECT_EQ(p.match().state_hash(), played().ticks.at(99).state_hash);
  EXPECT_EQ(p.seek(5).tick, 30u) << "nothing before the log's start";
  EXPECT_EQ(p.match().state_hash(), played().ticks.at(29).state_hash);
  ASSERT_TRUE(p.step());
  EXPECT_TRUE(p.last_hash_matched());
  EXPECT_EQ(p.tick(), 31u);
}

// begin_from(0) would be a log starting before tick 1: begin() is that.
TEST(StandbyLog, BeginFromNeedsATickAfterTheStart) {
  MatchLogWriter w((test_dir() / "x.tlog").string());
  EXPECT_THROW(w.begin_from(match_header(), 0, {}), LogError);
}

}  // namespace
}  // namespace throng::matchlog
