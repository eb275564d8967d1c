// The watchers of a played log, without DDS: who a spectator follows, what it is answered, what
// its snapshots carry, and when it is dropped (server/replay/play_watchers.h).
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "matchlog/matchlog_test_util.h"
#include "play_watchers.h"
#include "throng/core/object_id.h"
#include "throng/protocol/codec.h"
#include "throng/world/world.h"

namespace throng::replay {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

protocol::JoinRequest join(std::uint64_t nonce, const std::string& name = "watcher") {
  protocol::JoinRequest r;
  r.client_nonce = nonce;
  r.name = name;
  return r;
}

struct PlayWatchers : ::testing::Test {
  match::MatchConfig config = matchlog::test::small_config();
  match::Match match{matchlog::test::small_battle(), config, "watched"};
  match::Outbox out;
  Clock::time_point t0 = Clock::now();

  std::vector<protocol::JoinReply> logged_join(std::initializer_list<std::uint64_t> nonces) {
    for (auto n : nonces) match.inputs().push(join(n, "logged"));
    match.tick(out);
    return out.join_replies;
  }
};

TEST_F(PlayWatchers, WithNoLoggedClientAWatcherFollowsTheBodyNearestTheBattleCentre) {
  match.tick(out);
  const World& w = match.world();
  double cx = 0, cy = 0;
  for (std::size_t i = 0; i < w.pos_x().size(); ++i) {
    cx += w.pos_x()[i];
    cy += w.pos_y()[i];
  }
  cx /= static_cast<double>(w.pos_x().size());
  cy /= static_cast<double>(w.pos_x().size());
  std::uint32_t nearest = 0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < w.pos_x().size(); ++i) {
    const double d = std::hypot(w.pos_x()[i] - cx, w.pos_y()[i] - cy);
    if (d < best) best = d, nearest = w.id_at(i).value;
  }

  Watchers watchers(config.interest, {});
  WatcherChanges ch;
  watchers.handle_requests({join(11)}, match, false, t0, ch);
  ASSERT_EQ(ch.replies.size(), 1u);
  const auto& r = ch.replies[0];
  EXPECT_EQ(r.result, protocol::JoinResult::accepted);
  EXPECT_EQ(r.client_nonce, 11u);
  EXPECT_EQ(r.client_id, kWatcherIdBase + 1);
  EXPECT_EQ(r.snapshot_partition, "w1");
  EXPECT_EQ(r.entity, nearest);
  EXPECT_EQ(r.tick, 1u);
  ASSERT_EQ(ch.channels.size(), 1u);
  EXPECT_EQ(ch.channels[0].client_id, r.client_id);
  EXPECT_EQ(ch.channels[0].partition, "w1");

  // Its snapshots: its own id, the followed entity's exact pose, the world's poses around it.
  std::vector<protocol::Snapshot> snaps;
  std::vector<protocol::Pose> poses;
  for (int t = 0; t < 5; ++t) {
    match.tick(out);
    watchers.build_snapshots(match, snaps);
    ASSERT_EQ(snaps.size(), 1u);
    const auto& s = snaps[0];
    EXPECT_EQ(s.client_id, r.client_id);
    EXPECT_EQ(s.tick, match.tick_index());
    EXPECT_EQ(s.entity, nearest);
    EXPECT_EQ(s.last_applied_sequence, 0u);
    const Vec3 e = match.world().position(ObjectId{nearest});
    EXPECT_EQ(s.entity_x, static_cast<float>(e.x));
    EXPECT_EQ(s.entity_y, static_cast<float>(e.y));
    poses.clear();
    protocol::decode_poses(s, poses);
    if (t == 0) {
      EXPECT_GT(poses.size(), 20u) << "the first snapshot brings what is in view";
    }
    for (const auto& p : poses) {
      const Vec3 truth = match.world().position(ObjectId{p.id});
      EXPECT_NEAR(p.x, truth.x, 0.0005 + 1e-9);
      EXPECT_NEAR(p.y, truth.y, 0.0005 + 1e-9);
    }
  }
}

TEST_F(PlayWatchers, WatchersFollowTheLoggedClientsInTurn) {
  const auto logged = logged_join({101, 102, 103});
  ASSERT_EQ(logged.size(), 3u);
  Watchers watchers(config.interest, {});
  WatcherChanges ch;
  watchers.handle_requests({join(1), join(2), join(3), join(4)}, match, false, t0, ch);
  ASSERT_EQ(ch.replies.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(ch.replies[i].result, protocol::JoinResult::accepted);
    EXPECT_EQ(ch.replies[i].entity, logged[i % 3].entity) << "watcher " << i;
    EXPECT_EQ(ch.replies[i].faction, logged[i % 3].faction);
  }
  EXPECT_EQ(watchers.count(), 4u);
}

TEST_F(PlayWatchers, RefusalsRepeatsAndLeavesAreAnsweredLikeTheServerWould) {
  match.tick(out);
  Watchers watchers(config.interest, WatcherOptions{1, {}});
  WatcherChanges ch;
  auto old_version = join(5);
  old_version.protocol_version = 0;
  watchers.handle_requests({old_version, join(0), join(6, std::string(65, 'x')), join(7), join(7), join(8)}, match, false,
                           t0, ch);
  ASSERT_EQ(ch.replies.size(), 6u);
  EXPECT_EQ(ch.replies[0].result, protocol::JoinResult::bad_version);
  EXPECT_EQ(ch.replies[1].result, protocol::JoinResult::bad_request);
  EXPECT_EQ(ch.replies[2].result, protocol::JoinResult::bad_request);
  EXPECT_EQ(ch.replies[3].result, protocol::JoinResult::accepted);
  EXPECT_EQ(ch.replies[4].result, protocol::JoinResult::accepted) << "a retried join gets the same seat";
  EXPECT_EQ(ch.replies[4].client_id, ch.replies[3].client_id);
  EXPECT_EQ(ch.replies[5].result, protocol::JoinResult::match_full);
  EXPECT_EQ(ch.channels.size(), 1u);
  EXPECT_EQ(watchers.count(), 1u);

  const std::uint32_t id = ch.replies[3].client_id;
  ch.clear();
  watchers.handle_requests({join(9)}, match, /*ending=*/true, t0, ch);
  EXPECT_EQ(ch.replies.at(0).result, protocol::JoinResult::shutting_down);

  ch.clear();
  protocol::JoinRequest leave_unknown = join(10);
  leave_unknown.leave = true;
  leave_unknown.client_id = 3;  // a logged client's id: not the player's to release
  protocol::JoinRequest leave = join(12);
  leave.leave = true;
  leave.client_id = id;
  watchers.handle_requests({leave_unknown, leave}, match, false, t0, ch);
  ASSERT_EQ(ch.replies.size(), 2u);
  EXPECT_EQ(ch.replies[0].result, protocol::JoinResult::bad_request);
  EXPECT_EQ(ch.replies[1].result, protocol::JoinResult::left);
  ASSERT_EQ(ch.channels.size(), 1u);
  EXPECT_EQ(ch.channels[0].client_id, id);
  EXPECT_TRUE(ch.channels[0].partition.empty()) << "the channel is closed";
  EXPECT_EQ(watchers.count(), 0u);
  const auto& t = watchers.totals();
  EXPECT_EQ(t.joined, 1u);
  EXPECT_EQ(t.left, 1u);
  EXPECT_EQ(t.refused, 5u);
}

TEST_F(PlayWatchers, CommandsAreCountedAndKeepAWatcherAliveUntilItFallsSilent) {
  match.tick(out);
  Watchers watchers(config.interest, WatcherOptions{8, std::chrono::duration_cast<Clock::duration>(1s)});
  WatcherChanges ch;
  watchers.handle_requests({join(1)}, match, false, t0, ch);
  const std::uint32_t id = ch.replies.at(0).client_id;
  watchers.note_command(id, t0 + 800ms);
  watchers.note_command(7, t0 + 800ms);  // a logged client's id (its own bots still running): ignored too
  ch.clear();
  watchers.expire(t0 + 1500ms, ch);
  EXPECT_EQ(watchers.count(), 1u) << "heard 0.7 s ago";
  watchers.expire(t0 + 1900ms, ch);
  EXPECT_EQ(watchers.count(), 0u) << "silent for 1.1 s";
  ASSERT_EQ(ch.channels.size(), 1u);
  EXPECT_TRUE(ch.channels[0].partition.empty());
  EXPECT_EQ(watchers.totals().timed_out, 1u);
  EXPECT_EQ(watchers.totals().commands_ignored, 2u);
}

}  // namespace
}  // namespace throng::replay
