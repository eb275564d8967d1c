// A match reached over TCP only (--listen / --server): no multicast, no UDP discovery. Across
// network namespaces this is deploy/netns-match.sh (a ctest of its own); here both ends are on this
// host, the server on every interface and the client connecting to 127.0.0.1.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

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

// This process's established IPv4 TCP connections to `port` (from /proc: the sockets among its
// file descriptors whose remote end is that port).
int connections_to_port(std::uint16_t port) {
  std::set<std::string> own;
  for (const auto& fd : std::filesystem::directory_iterator("/proc/self/fd")) {
    std::error_code ec;
    const std::string target = std::filesystem::read_symlink(fd.path(), ec).string();
    if (!ec && target.rfind("socket:[", 0) == 0) own.insert(target.substr(8, target.size() - 9));
  }
  std::ifstream tcp("/proc/self/net/tcp");
  std::string line;
  std::getline(tcp, line);  // the header
  int count = 0;
  while (std::getline(tcp, line)) {
    std::istringstream in(line);
    std::string slot, local, remote, state, queues, timer, retransmits, uid, timeout, inode;
    in >> slot >> local >> remote >> state >> queues >> timer >> retransmits >> uid >> timeout >> inode;
    const auto colon = remote.find(':');
    if (state != "01" || colon == std::string::npos) continue;  // 01: ESTABLISHED
    if (std::stoul(remote.substr(colon + 1), nullptr, 16) == port && own.count(inode) > 0) ++count;
  }
  return count;
}

// A server listening on TCP never connects to its own listener. With the hot-standby endpoints,
// its primary-claim writer matched its own reader, and Fast DDS 2.9 connected the server to
// itself: a connection whose two channels the transport cannot tell apart, and whose forgotten
// receive thread could crash the server as it exited.
TEST(ServerTcp, AServerOnTcpNeverConnectsToItself) {
  const std::uint16_t port = free_tcp_port();
  auto o = small_server_options(165);
  o.listen = "tcp://0.0.0.0:" + std::to_string(port);
  ServerThread server(o);
  // The self-connection appeared within a second of the start; no client is on this port.
  std::this_thread::sleep_for(2s);
  EXPECT_EQ(connections_to_port(port), 0) << "the server connected to its own TCP listener";
  server.stop();
  EXPECT_EQ(server.exit_code(), 0);
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
