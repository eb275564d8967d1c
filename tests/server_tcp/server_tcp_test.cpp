// A match reached over TCP only (--listen / --server): no multicast, no UDP discovery. Across
// network namespaces this is deploy/netns-match.sh (a ctest of its own); here both ends are on this
// host, the server on every interface and the client connecting to 127.0.0.1.
#include <gtest/gtest.h>

#include "server_test_support.h"

namespace throng::test {
namespace {

TEST(ServerTcp, AClientJoinsAndPlaysOverTcpOnly) {
  const std::uint16_t port = free_tcp_port();
  auto o = small_server_options(164);
  o.listen = "tcp://0.0.0.0:" + std::to_string(port);
  ServerThread server(o);
  const TcpJoin joined = join_over_tcp(164, port, "over-tcp", 77);
  ASSERT_TRUE(joined.accepted());
  TestClient& client = *joined.client;
  const auto& r = joined.reply;
  client.transport().send_command(standing_command(*r, 1));
  EXPECT_TRUE(client.wait_until([&] { return last_applied(client.snapshots(), r->client_id) == 1; }))
      << "no snapshot confirmed the command";
  // Nothing of the match went over the domain's UDP discovery: a plain loopback client on the
  // same domain finds no server.
  protocol::TransportOptions plain{164, true, "udp-client", std::nullopt};
  protocol::ClientTransport udp(plain);
  udp.start({});
  EXPECT_FALSE(udp.wait_for_server(2s)) << "the TCP-only server was reachable without TCP";
}

TEST(ServerTcp, ALoopbackOnlyListenerIsRefusedWithTheReason) {
  auto o = small_server_options(165);
  o.listen = "tcp://127.0.0.1:7400";
  try {
    server::MatchServer s(o);
    ADD_FAILURE() << "a loopback TCP listener was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("listen on 0.0.0.0"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace throng::test
