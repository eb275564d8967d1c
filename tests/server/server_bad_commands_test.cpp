// Every kind of bad command is rejected and counted by reason, and the world ends in exactly the
// state it reaches without them: the server's final state hash equals an offline re-simulation of
// the same match fed only the join and the one valid command, at the ticks the server applied them.
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "server_test_support.h"
#include "throng/match/match.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"

namespace throng::test {
namespace {

TEST(ServerBadCommands, EveryBadCommandIsRejectedByReasonAndChangesNothing) {
  auto options = small_server_options(145);
  options.match.max_commands_per_tick = 1;
  std::optional<std::uint64_t> join_tick, applied_tick;
  std::uint64_t sent = 0;
  nlohmann::json summary;
  protocol::JoinReply reply;
  {
    ServerThread server(options);
    TestClient client(145);
    const auto r = client.join(4242, "mallory");
    ASSERT_TRUE(r && r->result == protocol::JoinResult::accepted);
    reply = *r;
    ASSERT_TRUE(client.wait_until([&] { return !client.snapshots().empty(); }));

    auto send = [&](const protocol::Command& c) {
      client.transport().send_command(c);
      ++sent;
      std::this_thread::sleep_for(5ms);
    };
    // One valid command (zero move, fixed camera); learn the tick it was applied in.
    send(standing_command(reply, 1));
    ASSERT_TRUE(client.wait_until([&] { return client.snapshots().back().last_applied_sequence == 1; }));
    applied_tick = client.with_lock([&] { return client.snapshots().back().last_applied_tick; });
    std::this_thread::sleep_for(100ms);

    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    auto c = standing_command(reply, 100);
    c.move_x = nan;                         send(c);  // non_finite
    c = standing_command(reply, 101); c.camera_z = inf; send(c);  // non_finite
    c = standing_command(reply, 102); c.move_x = 0.9f; c.move_y = 0.9f; send(c);  // move_out_of_range (|m| = 1.27)
    c = standing_command(reply, 103); c.facing_rad = 4.0f;  send(c);   // facing_out_of_range
    c = standing_command(reply, 104); c.camera_x = 1e9f;    send(c);   // camera_out_of_range
    c = standing_command(reply, 105); c.actions = 1u << 7;  send(c);   // bad_actions
    c = standing_command(reply, 106); c.client_id = 999;    send(c);   // unknown_client
    c = standing_command(reply, 107); c.entity = reply.entity + 1; send(c);  // not_your_entity
    c = standing_command(reply, 1);                          send(c);   // duplicate_sequence
    c = standing_command(reply, 0);                          send(c);   // stale_sequence
    // foreign_participant: mallory's own id, entity and a fresh sequence, from another participant.
    TestClient stranger(145);
    ASSERT_TRUE(stranger.transport().wait_for_server(10s));
    ASSERT_TRUE(wait_for_command_writers(server, 2));
    c = standing_command(reply, 108); c.move_x = 1.0f;
    stranger.transport().send_command(c);
    ++sent;
    std::this_thread::sleep_for(300ms);
    server.stop();
    EXPECT_EQ(server.exit_code(), 0);
    summary = server.server().summary();
    for (const auto& cl : summary["clients"])
      if (cl["name"] == "mallory") join_tick = cl["joined_tick"].get<std::uint64_t>();
  }
  ASSERT_TRUE(join_tick.has_value());
  ASSERT_TRUE(applied_tick.has_value());

  const auto& by = summary["rejected_by_reason"];
  EXPECT_EQ(by["non_finite"], 2);
  EXPECT_EQ(by["move_out_of_range"], 1);
  EXPECT_EQ(by["facing_out_of_range"], 1);
  EXPECT_EQ(by["camera_out_of_range"], 1);
  EXPECT_EQ(by["bad_actions"], 1);
  EXPECT_EQ(by["unknown_client"], 1);
  EXPECT_EQ(by["not_your_entity"], 1);
  EXPECT_EQ(by["duplicate_sequence"], 1);
  EXPECT_EQ(by["stale_sequence"], 1);
  EXPECT_EQ(by["foreign_participant"], 1);
  EXPECT_EQ(summary["commands_accepted"], 1);
  EXPECT_EQ(summary["commands_accepted"].get<std::uint64_t>() + summary["commands_rejected"].get<std::uint64_t>(), sent);

  // Offline: same scene and config, only the join and the valid command, at the same ticks.
  const auto scene = scene::scale_scene(scene::builtin_scene("battle"), options.npcs);
  match::Match offline(scene, options.match, "offline");
  match::Outbox out;
  const auto ticks = summary["ticks"].get<std::uint64_t>();
  for (std::uint64_t t = 1; t <= ticks; ++t) {
    if (t == *join_tick) {
      protocol::JoinRequest j;
      j.client_nonce = 4242;
      j.name = "mallory";
      offline.inputs().push(std::move(j));
    }
    if (t == *applied_tick) offline.inputs().push(standing_command(reply, 1));
    if (t == ticks) offline.begin_shutdown();
    offline.tick(out);
  }
  EXPECT_EQ(fmt::format("{:016x}", offline.state_hash()), summary["state_hash"].get<std::string>())
      << "rejected commands changed the world (join tick " << *join_tick << ", command tick " << *applied_tick << ")";
}

TEST(ServerBadCommands, MoreCommandsThanTheRateLimitInOneTickAreRejected) {
  auto options = small_server_options(146);
  options.match.max_commands_per_tick = 1;
  ServerThread server(options);
  TestClient client(146);
  const auto r = client.join(5, "flooder");
  ASSERT_TRUE(r && r->result == protocol::JoinResult::accepted);
  std::uint64_t sent = 0;
  std::uint32_t seq = 0;
  for (int burst = 0; burst < 5; ++burst) {
    for (int i = 0; i < 4; ++i, ++sent) client.transport().send_command(standing_command(*r, ++seq));
    std::this_thread::sleep_for(100ms);
  }
  std::this_thread::sleep_for(200ms);
  server.stop();
  const auto s = server.server().summary();
  EXPECT_GE(s["rejected_by_reason"]["rate_limited"].get<std::uint64_t>(), 5u) << s.dump();
  EXPECT_EQ(s["commands_accepted"].get<std::uint64_t>() + s["commands_rejected"].get<std::uint64_t>(), sent);
}

}  // namespace
}  // namespace throng::test
