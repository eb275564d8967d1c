// How a playback ends: at the end of the log ('ended' published, exit 0), and on a log this
// build does not reproduce (said loudly, exit 1; --strict stops at the first mismatch). Watchers'
// parameter updates are refused and their leave is answered.
#include <algorithm>

#include <gtest/gtest.h>

#include "play_test_support.h"

namespace throng::play_test {
namespace {

TEST(PlayEnd, PlaysToTheEndOfTheLogAndEndsTheMatch) {
  constexpr int kDomain = 212;
  test::TempDir dir("throng-play-end");
  const auto log = dir / "match.tlog";
  record_log(log, 300);  // 10 s at 30 Hz
  auto player = start_player(log, kDomain, {}, dir);

  Watcher w(kDomain);
  const auto reply = w.join(5, "short-visit");
  ASSERT_TRUE(reply && reply->result == protocol::JoinResult::accepted) << test::read_file(dir / "play.err");
  ASSERT_TRUE(w.wait_until([&] { return !w.own_snapshots().empty(); })) << test::read_file(dir / "play.err");

  // An operator change is refused: the logged match takes no new inputs.
  protocol::ParamUpdate u;
  u.request_id = 4242;
  u.entity = reply->entity;
  u.param = "weight_kg";
  u.value = 500.0;
  w.transport().send_param_update(u);
  ASSERT_TRUE(w.wait_until([&] {
    return std::any_of(w.param_replies().begin(), w.param_replies().end(), [](const auto& r) { return r.request_id == 4242; });
  })) << test::read_file(dir / "play.err");
  w.with_lock([&] {
    for (const auto& r : w.param_replies()) {
      if (r.request_id != 4242) continue;
      EXPECT_FALSE(r.ok);
      EXPECT_NE(r.error.find("replay"), std::string::npos) << r.error;
    }
  });

  // Leaving is answered like the server answers it.
  protocol::JoinRequest leave;
  leave.client_nonce = 6;
  leave.leave = true;
  leave.client_id = reply->client_id;
  w.transport().send_join(leave);
  ASSERT_TRUE(w.wait_until([&] {
    return std::any_of(w.replies().begin(), w.replies().end(),
                       [](const auto& r) { return r.client_nonce == 6 && r.result == protocol::JoinResult::left; });
  }));

  // The player stops by itself at the end of the log, and the match ended for everyone.
  EXPECT_EQ(player->wait(40s), 0) << test::read_file(dir / "play.err");
  EXPECT_TRUE(w.wait_until([&] { return !w.infos().empty() && w.infos().back().state == protocol::MatchState::ended; }, 10s));
  EXPECT_TRUE(w.wait_until([&] { return !w.stats().empty() && w.stats().back().state == protocol::MatchState::ended; }, 10s));
  w.with_lock([&] {
    ASSERT_FALSE(w.stats().empty());
    EXPECT_EQ(w.stats().back().tick, 300u);
    EXPECT_EQ(w.stats().back().tick_hz, 30u);
    EXPECT_GT(w.stats().back().bodies, 250u);
  });
  const std::string out = test::read_file(dir / "play.out");
  EXPECT_NE(out.find("stopped by: the end of the log at tick 300"), std::string::npos) << out;
  EXPECT_NE(out.find("ticks played: 300 "), std::string::npos) << out;
  EXPECT_NE(out.find("hash mismatches: 0"), std::string::npos) << out;
  EXPECT_NE(out.find("1 joined, 0 refused, 1 left"), std::string::npos) << out;
  EXPECT_NE(out.find("1 parameter updates refused"), std::string::npos) << out;
}

TEST(PlayEnd, ALogThisBuildDoesNotReproduceIsSaidLoudly) {
  constexpr int kDomain = 213;
  test::TempDir dir("throng-play-mismatch");
  const auto log = dir / "tampered.tlog";
  record_log(log, 120, /*tamper_tick=*/50);
  auto player = start_player(log, kDomain, {"--speed", "16"}, dir);
  EXPECT_EQ(player->wait(40s), 1) << test::read_file(dir / "play.err");
  const std::string err = test::read_file(dir / "play.err");
  EXPECT_NE(err.find("HASH MISMATCH at tick 50: this build does NOT reproduce the log"), std::string::npos) << err;
  const std::string out = test::read_file(dir / "play.out");
  EXPECT_NE(out.find("stopped by: the end of the log at tick 120"), std::string::npos) << "it plays on: " << out;
  EXPECT_NE(out.find("hash mismatches: 1 (first at tick 50)"), std::string::npos) << out;
}

TEST(PlayEnd, StrictStopsAtTheFirstMismatch) {
  constexpr int kDomain = 214;
  test::TempDir dir("throng-play-strict");
  const auto log = dir / "tampered.tlog";
  record_log(log, 120, /*tamper_tick=*/50);
  auto player = start_player(log, kDomain, {"--speed", "16", "--strict"}, dir);
  EXPECT_EQ(player->wait(40s), 1) << test::read_file(dir / "play.err");
  const std::string out = test::read_file(dir / "play.out");
  EXPECT_NE(out.find("stopped by: a hash mismatch (--strict) at tick 50"), std::string::npos) << out;
  EXPECT_NE(out.find("ticks played: 50 "), std::string::npos) << out;
}

}  // namespace
}  // namespace throng::play_test
