// A DDS client watching `throng-replay play`: the match info is the logged match's, a joiner is
// accepted as a spectator, the logged clients' partitions carry exactly the snapshots the live
// server built (checked field by field against a LogPlayer in the test), the spectator's own
// stream carries the re-simulated world's poses, and SIGTERM ends it with 'ended' and exit 0.
#include <algorithm>
#include <csignal>
#include <map>
#include <set>
#include <thread>

#include <gtest/gtest.h>

#include "play_test_support.h"
#include "protocol/message_equality.h"
#include "throng/core/object_id.h"
#include "throng/matchlog/log_player.h"
#include "throng/protocol/codec.h"
#include "throng/world/world.h"

namespace throng::play_test {
namespace {

constexpr std::uint64_t kTicks = 300;
constexpr std::uint64_t kFrom = 100;

const protocol::Snapshot* snapshot_of(const match::Outbox& out, std::uint32_t client_id) {
  for (std::size_t i = 0; i < out.snapshot_count; ++i)
    if (out.snapshots[i].client_id == client_id) return &out.snapshots[i];
  return nullptr;
}

TEST(PlayWatch, ClientSeesTheLoggedMatchAsTheServerPublishedIt) {
  constexpr int kDomain = 210;
  test::TempDir dir("throng-play-watch");
  const auto log = dir / "match.tlog";
  record_log(log, kTicks);
  auto player = start_player(log, kDomain, {"--from", std::to_string(kFrom), "--loop", "--watcher-timeout", "0"}, dir);

  // What the logged match looked like at the playback's start (ops changes at 40 and 90 are in).
  matchlog::LogPlayer ref(log.string());
  ref.seek(kFrom - 1);
  const protocol::MatchInfo expected_info = ref.match().match_info();
  std::uint32_t client1_entity = 0;
  for (const auto& c : ref.match().clients())
    if (c.client_id == 1) client1_entity = c.entity;
  ASSERT_NE(client1_entity, 0u);

  Watcher w(kDomain);
  const auto reply = w.join(77, "spectator");
  ASSERT_TRUE(reply) << test::read_file(dir / "play.err");
  ASSERT_EQ(reply->result, protocol::JoinResult::accepted) << reply->reason;
  EXPECT_GT(reply->client_id, 1'000'000'000u) << "a watcher never takes a logged client's id";
  EXPECT_EQ(reply->snapshot_partition.rfind("w", 0), 0u) << reply->snapshot_partition;
  EXPECT_EQ(reply->entity, client1_entity) << "the first watcher follows the first logged client's entity";
  w.listen(1, "c1");  // the logged client 1's own partition, as the live server wrote it

  // Commands from a spectator reach the player and are ignored; they also keep it alive.
  std::uint32_t sequence = 0;
  auto have_enough = [&] { return w.own_snapshots().size() >= 40 && w.logged_snapshots().size() >= 40; };
  bool enough = false;
  for (int i = 0; i < 200 && !enough; ++i) {  // bounded: 200 x 100 ms
    protocol::Command c;
    c.client_id = reply->client_id;
    c.entity = reply->entity;
    c.sequence = ++sequence;
    c.move_x = 1.0f;
    w.transport().send_command(c);
    enough = w.wait_until(have_enough, 100ms);
  }
  ASSERT_TRUE(enough) << test::read_file(dir / "play.err");

  player->signal(SIGTERM);
  EXPECT_EQ(player->wait(20s), 0) << test::read_file(dir / "play.err");
  EXPECT_TRUE(w.wait_until([&] { return !w.infos().empty() && w.infos().back().state == protocol::MatchState::ended; }, 10s))
      << "watchers are told the match ended";
  const std::string out = test::read_file(dir / "play.out");
  EXPECT_NE(out.find("stopped by: SIGTERM"), std::string::npos) << out;
  EXPECT_NE(out.find("hash mismatches: 0"), std::string::npos) << out;
  EXPECT_NE(out.find("watchers: 1 joined"), std::string::npos) << out;
  EXPECT_EQ(out.find(" 0 commands ignored"), std::string::npos) << "the spectator's commands were counted: " << out;

  // Everything received, compared with the re-simulation tick by tick.
  std::vector<protocol::MatchInfo> infos;
  std::map<std::uint64_t, std::vector<protocol::Snapshot>> logged, own;
  w.with_lock([&] {
    infos = w.infos();
    for (auto& s : w.logged_snapshots()) logged[s.tick].push_back(s);
    for (auto& s : w.own_snapshots()) own[s.tick].push_back(s);
  });
  bool saw_running = false;
  for (const auto& info : infos) {
    if (info.state != protocol::MatchState::running) continue;
    saw_running = true;
    protocol::test::expect_same(info, expected_info);
  }
  EXPECT_TRUE(saw_running);
  EXPECT_GE(logged.begin()->first, kFrom) << "nothing before --from is published";

  matchlog::LogPlayer sim(log.string());
  std::size_t logged_checked = 0, poses_checked = 0;
  std::vector<protocol::Pose> poses;
  while (sim.step()) {
    const std::uint64_t t = sim.tick();
    if (auto it = logged.find(t); it != logged.end()) {
      const protocol::Snapshot* truth = snapshot_of(sim.outbox(), 1);
      ASSERT_NE(truth, nullptr) << "tick " << t;
      for (const auto& s : it->second) {
        SCOPED_TRACE("logged client 1, tick " + std::to_string(t));
        protocol::test::expect_same(s, *truth);
        ++logged_checked;
      }
    }
    if (auto it = own.find(t); it != own.end()) {
      const World& world = sim.match().world();
      for (const auto& s : it->second) {
        SCOPED_TRACE("spectator, tick " + std::to_string(t));
        EXPECT_EQ(s.client_id, reply->client_id);
        EXPECT_EQ(s.entity, client1_entity);
        const Vec3 e = world.position(ObjectId{client1_entity});
        EXPECT_EQ(s.entity_x, static_cast<float>(e.x));
        EXPECT_EQ(s.entity_y, static_cast<float>(e.y));
        poses.clear();  // decode_poses appends
        protocol::decode_poses(s, poses);
        const double tol = s.unit_mm * 0.5e-3 + 1e-9;
        for (const auto& p : poses) {
          const Vec3 truth = world.position(ObjectId{p.id});
          EXPECT_NEAR(p.x, truth.x, tol) << "object " << p.id;
          EXPECT_NEAR(p.y, truth.y, tol) << "object " << p.id;
          EXPECT_NEAR(p.z, truth.z, tol) << "object " << p.id;
          ++poses_checked;
        }
      }
    }
  }
  EXPECT_GE(logged_checked, 40u);
  EXPECT_GE(poses_checked, 400u) << "the spectator stream carries poses";
  // The spectator's stream is its own picture of the battle around the followed entity.
  std::set<std::uint32_t> seen;
  for (const auto& [t, v] : own)
    for (const auto& s : v) {
      poses.clear();  // decode_poses appends
      protocol::decode_poses(s, poses);
      for (const auto& p : poses) seen.insert(p.id);
    }
  EXPECT_GT(seen.size(), 20u);
}

}  // namespace
}  // namespace throng::play_test
