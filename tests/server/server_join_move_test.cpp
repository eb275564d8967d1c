// A client joins over DDS, drives its entity with commands and sees it move in its snapshots;
// the server echoes the newest applied command sequence (latency measurement).
#include <gtest/gtest.h>

#include "server_test_support.h"

namespace throng::test {
namespace {

TEST(ServerJoinMove, ClientJoinsCommandsAndSeesItsEntityMove) {
  ServerThread server(small_server_options(141));
  TestClient client(141);
  const auto reply = client.join(0xC0FFEE, "mover");
  ASSERT_TRUE(reply.has_value()) << "no join reply within 10 s";
  ASSERT_EQ(reply->result, protocol::JoinResult::accepted) << reply->reason;
  EXPECT_EQ(reply->client_id, 1u);
  EXPECT_NE(reply->entity, 0u);
  EXPECT_EQ(reply->snapshot_partition, "c1");

  // The first snapshots (before any command) give the start position.
  ASSERT_TRUE(client.wait_until([&] { return !client.snapshots().empty(); }));
  const auto first = client.with_lock([&] { return client.snapshots().front(); });
  EXPECT_EQ(first.entity, reply->entity);
  EXPECT_EQ(first.last_applied_sequence, 0u);

  // Full stick towards +y for ~1 s (one command per tick).
  std::uint32_t seq = 0;
  for (int i = 0; i < 30; ++i) {
    protocol::Command c;
    c.client_id = reply->client_id;
    c.entity = reply->entity;
    c.sequence = ++seq;
    c.move_y = 1.0f;
    c.facing_rad = 1.5707964f;
    c.camera_x = first.entity_x;
    c.camera_y = first.entity_y;
    client.transport().send_command(c);
    std::this_thread::sleep_for(33ms);
  }
  ASSERT_TRUE(client.wait_until([&] { return client.snapshots().back().last_applied_sequence >= seq - 2; }))
      << "the server never reported the last commands as applied";
  const auto last = client.with_lock([&] { return client.snapshots().back(); });
  EXPECT_GT(last.tick, first.tick);
  // Player speed 4 m/s for ~1 s, pushed about by the crowd: it must have gone clearly north.
  EXPECT_GT(last.entity_y - first.entity_y, 1.0) << "entity did not move in the commanded direction";
  EXPECT_NEAR(last.entity_yaw, 1.5707964, 0.05);
  // Snapshot ticks strictly increase (one sample per tick, none duplicated).
  client.with_lock([&] {
    for (std::size_t i = 1; i < client.snapshots().size(); ++i)
      EXPECT_GT(client.snapshots()[i].tick, client.snapshots()[i - 1].tick);
    return 0;
  });
}

TEST(ServerJoinMove, AClientWithAnotherProtocolVersionIsRefused) {
  ServerThread server(small_server_options(142));
  TestClient client(142);
  const auto reply = client.join(77, "old-build", protocol::kProtocolVersion + 1);
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(reply->result, protocol::JoinResult::bad_version);
  EXPECT_NE(reply->reason.find(std::to_string(protocol::kProtocolVersion)), std::string::npos) << reply->reason;
  EXPECT_EQ(reply->entity, 0u);
}

TEST(ServerJoinMove, JoinsBeyondMaxClientsAreRefusedAsMatchFull) {
  auto o = small_server_options(143);
  o.match.max_clients = 1;
  ServerThread server(o);
  TestClient a(143);
  const auto ra = a.join(1, "first");
  ASSERT_TRUE(ra && ra->result == protocol::JoinResult::accepted);
  const auto rb = a.join(2, "second");
  ASSERT_TRUE(rb.has_value());
  EXPECT_EQ(rb->result, protocol::JoinResult::match_full);
}

}  // namespace
}  // namespace throng::test
