// A match reached over the NAT-crossing UDP path only (--listen udp:// / --server udp://): no
// multicast, no well-known ports, one UDP socket per participant. Through a real (emulated) NAT
// this is deploy/internet-match.sh and tests/link; here both ends are on 127.0.0.1.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "server_test_support.h"
#include "throng/protocol/security.h"

namespace throng::test {
namespace {

namespace fs = std::filesystem;

// A UDP port on 127.0.0.1 nobody holds now, below the ephemeral range.
std::uint16_t free_udp_port() {
  const auto first = static_cast<std::uint16_t>(20000 + (::getpid() * 61) % 12000);
  for (std::uint32_t k = 0; k < 12000; ++k) {
    const auto port = static_cast<std::uint16_t>(20000 + (first - 20000 + k) % 12000);
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(port);
    const bool free = ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
    ::close(fd);
    if (free) return port;
  }
  return 0;
}

protocol::TransportOptions udp_client(int domain, std::uint16_t port, const std::string& name) {
  protocol::TransportOptions t{domain, true, name, std::nullopt};
  t.server_endpoint = protocol::NetEndpoint{"127.0.0.1", port, protocol::NetEndpoint::Scheme::udp};
  return t;
}

server::ServerOptions udp_server(int domain, std::uint16_t port) {
  auto o = small_server_options(domain);
  o.listen = "udp://127.0.0.1:" + std::to_string(port);
  return o;
}

TEST(ServerUdp, AClientJoinsAndPlaysOverUdpOnly) {
  const std::uint16_t port = free_udp_port();
  ServerThread server(udp_server(151, port));
  TestClient client(udp_client(151, port, "over-udp"), 12s);
  const auto r = client.join(91, "over-udp");
  ASSERT_TRUE(r && r->result == protocol::JoinResult::accepted);
  client.transport().send_command(standing_command(*r, 1));
  EXPECT_TRUE(client.wait_until([&] { return last_applied(client.snapshots(), r->client_id) == 1; }))
      << "no snapshot confirmed the command";
  // The match is on that port only: a plain loopback client on the same domain finds no server.
  protocol::ClientTransport plain(protocol::TransportOptions{151, true, "plain-udp", std::nullopt});
  plain.start({});
  EXPECT_FALSE(plain.wait_for_server(2s)) << "the server was reachable without --server udp://";
}

// Each participant has its own socket and token, so two of one process are two players to the
// server (over TCP, Fast DDS 2.9 mistakes the second for the first).
TEST(ServerUdp, TwoParticipantsOfOneProcessAreTwoPlayers) {
  const std::uint16_t port = free_udp_port();
  ServerThread server(udp_server(153, port));
  TestClient a(udp_client(153, port, "udp-a"), 12s), b(udp_client(153, port, "udp-b"), 12s);
  const auto ra = a.join(1001, "udp-a");
  const auto rb = b.join(1002, "udp-b");
  ASSERT_TRUE(ra && ra->result == protocol::JoinResult::accepted);
  ASSERT_TRUE(rb && rb->result == protocol::JoinResult::accepted);
  ASSERT_NE(ra->client_id, rb->client_id);
  a.transport().send_command(standing_command(*ra, 1));
  b.transport().send_command(standing_command(*rb, 1));
  EXPECT_TRUE(a.wait_until([&] { return last_applied(a.snapshots(), ra->client_id) == 1; }));
  EXPECT_TRUE(b.wait_until([&] { return last_applied(b.snapshots(), rb->client_id) == 1; }));
  EXPECT_EQ(snapshots_of(a.snapshots(), rb->client_id), 0u) << "a received b's snapshots";
  EXPECT_EQ(snapshots_of(b.snapshots(), ra->client_id), 0u) << "b received a's snapshots";
}

// DDS Security's handshake carries certificates and a permissions document of several kB, more
// than one datagram: the transport sends it in pieces and the receiver puts it back together.
TEST(ServerUdp, DdsSecurityWorksOverIt) {
  const fs::path dir = fs::temp_directory_path() / ("throng_udp_pki_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string cmd = std::string(THRONG_BIN_DIR) + "/throng-pki init " + dir.string() + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  ASSERT_GT(fs::file_size(dir / "bots" / "permissions.p7s"), 1400u) << "the handshake would fit in one datagram";
  const std::uint16_t port = free_udp_port();
  auto o = udp_server(159, port);
  o.security_dir = dir.string();
  ServerThread server(o);
  auto t = udp_client(159, port, "secure-udp");
  t.security = protocol::security_files(dir.string(), "bots");
  TestClient client(t, 20s);
  const auto r = client.join(77, "secure-udp");
  ASSERT_TRUE(r && r->result == protocol::JoinResult::accepted);
  client.transport().send_command(standing_command(*r, 1));
  EXPECT_TRUE(client.wait_until([&] { return last_applied(client.snapshots(), r->client_id) == 1; }));
  fs::remove_all(dir);
}

TEST(ServerUdp, AListenerOnEveryInterfaceNeedsThePublicAddress) {
  const std::uint16_t port = free_udp_port();
  protocol::TransportOptions t{161, true, "no-public", std::nullopt};
  t.listen_endpoint = protocol::NetEndpoint{"0.0.0.0", port, protocol::NetEndpoint::Scheme::udp};
  try {
    protocol::ServerTransport s(t);
    FAIL() << "a UDP listener on 0.0.0.0 without a public address was accepted";
  } catch (const protocol::TransportError& e) {
    EXPECT_NE(std::string(e.what()).find("--public-address"), std::string::npos) << e.what();
  }
  t.public_address = "127.0.0.1";
  EXPECT_NO_THROW(protocol::ServerTransport s(t));
}

TEST(ServerUdp, APortInUseIsRefusedWithTheReason) {
  const std::uint16_t port = free_udp_port();
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(port);
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  protocol::TransportOptions t{161, true, "busy", std::nullopt};
  t.listen_endpoint = protocol::NetEndpoint{"127.0.0.1", port, protocol::NetEndpoint::Scheme::udp};
  try {
    protocol::ServerTransport s(t);
    FAIL() << "a busy port was accepted";
  } catch (const protocol::TransportError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot listen on udp://127.0.0.1:" + std::to_string(port)), std::string::npos)
        << e.what();
  }
  ::close(fd);
}

}  // namespace
}  // namespace throng::test
