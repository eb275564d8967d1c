// A client that vanishes (stops sending commands) is detected after the configured timeout, its
// entity handed back to the AI, and the departure recorded.
#include <gtest/gtest.h>

#include "server_test_support.h"

namespace throng::test {
namespace {

TEST(ServerLiveness, AClientThatStopsSendingIsTimedOut) {
  auto options = small_server_options(147);
  options.match.client_timeout_s = 0.5;
  ServerThread server(options);
  std::uint32_t client_id = 0;
  {
    TestClient client(147);
    const auto r = client.join(99, "ghost");
    ASSERT_TRUE(r && r->result == protocol::JoinResult::accepted);
    client_id = r->client_id;
    ASSERT_TRUE(client.wait_until([&] { return !client.snapshots().empty(); }));
  }  // the client process "dies": its participant is gone, no leave message
  std::this_thread::sleep_for(1500ms);  // 3x the timeout
  server.stop();
  const auto s = server.server().summary();
  ASSERT_EQ(s["clients"].size(), 1u);
  const auto& c = s["clients"][0];
  EXPECT_EQ(c["client_id"], client_id);
  EXPECT_EQ(c["departure"], "timed_out");
  // Timed out 0.5 s (15 ticks at 30 Hz) after the join: never earlier.
  EXPECT_GE(c["departed_tick"].get<std::uint64_t>(), c["joined_tick"].get<std::uint64_t>() + 15);
  EXPECT_EQ(s["clients_connected_at_end"], 0);
}

TEST(ServerLiveness, ALeaveMessageEndsTheSessionAtOnce) {
  ServerThread server(small_server_options(148));
  TestClient client(148);
  const auto r = client.join(7, "polite");
  ASSERT_TRUE(r && r->result == protocol::JoinResult::accepted);
  ASSERT_TRUE(client.leave(7, r->client_id)) << "no reply to the leave";
  server.stop();
  const auto s = server.server().summary();
  ASSERT_EQ(s["clients"].size(), 1u);
  EXPECT_EQ(s["clients"][0]["departure"], "left");
}

}  // namespace
}  // namespace throng::test
