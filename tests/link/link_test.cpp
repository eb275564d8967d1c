// The forwarding loop over two datagram socket pairs standing in for the TUN devices.
#include <gtest/gtest.h>

#include <sys/socket.h>
#include <unistd.h>
#include <poll.h>

#include <thread>

#include "packet_builder.h"
#include "throng/link/link.h"
#include "throng/link/link_report.h"

namespace throng::link {
namespace {

using testing::ip;
using testing::make_packet;

struct Pair {
  int inner = -1, outer = -1;  // the link holds inner; the test plays the kernel on outer
  Pair() {
    int fds[2];
    EXPECT_EQ(::socketpair(AF_UNIX, SOCK_DGRAM | SOCK_NONBLOCK, 0, fds), 0);
    inner = fds[0];
    outer = fds[1];
  }
  ~Pair() {
    ::close(inner);
    ::close(outer);
  }
};

std::optional<std::vector<std::uint8_t>> receive(int fd, int timeout_ms) {
  pollfd p{fd, POLLIN, 0};
  if (::poll(&p, 1, timeout_ms) <= 0) return std::nullopt;
  std::vector<std::uint8_t> b(2048);
  const ssize_t n = ::read(fd, b.data(), b.size());
  if (n <= 0) return std::nullopt;
  b.resize(static_cast<std::size_t>(n));
  return b;
}

TEST(Link, CarriesPacketsBothWaysThroughTheNatAfterTheirDelay) {
  Pair client, server;
  LinkConfig c;
  c.up.delay = std::chrono::milliseconds(30);
  c.down.delay = std::chrono::milliseconds(10);
  NatConfig nat;
  nat.public_address = ip("10.77.0.100");
  c.nat = nat;
  Link link(c, client.inner, server.inner);
  std::atomic<bool> stop{false};
  std::thread loop([&] { link.run(stop, std::chrono::steady_clock::now() + std::chrono::seconds(10)); });

  const auto up = make_packet(17, ip("10.77.1.2"), 5000, ip("10.77.0.1"), 7400);
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(::write(client.outer, up.data(), up.size()), static_cast<ssize_t>(up.size()));
  const auto arrived = receive(server.outer, 2000);
  const auto took = std::chrono::steady_clock::now() - t0;
  ASSERT_TRUE(arrived);
  EXPECT_GE(took, std::chrono::milliseconds(30));
  const PacketHeader h = *parse_ipv4(*arrived);
  EXPECT_EQ(h.source, ip("10.77.0.100"));
  EXPECT_EQ(transport_checksum(*arrived), 0);

  // The server's answer to the public endpoint comes home; one from another port does not.
  const auto reply = make_packet(17, ip("10.77.0.1"), 7400, ip("10.77.0.100"), h.source_port);
  const auto stranger = make_packet(17, ip("10.77.0.1"), 7999, ip("10.77.0.100"), h.source_port);
  ASSERT_GT(::write(server.outer, stranger.data(), stranger.size()), 0);
  ASSERT_GT(::write(server.outer, reply.data(), reply.size()), 0);
  const auto home = receive(client.outer, 2000);
  ASSERT_TRUE(home);
  EXPECT_EQ(parse_ipv4(*home)->destination_port, 5000);
  EXPECT_EQ(parse_ipv4(*home)->source_port, 7400);
  EXPECT_FALSE(receive(client.outer, 200));  // the stranger's was filtered (waited for past its delay)

  stop = true;
  loop.join();
  EXPECT_EQ(link.counters().nat_dropped_down, 1u);
  EXPECT_EQ(link.nat()->counters().filtered, 1u);
  const auto j = report_json(link, c);
  EXPECT_EQ(j["up"]["delivered"], 1);
  EXPECT_EQ(j["down"]["packets"], 2);
  EXPECT_EQ(j["nat"]["filtered"], 1);
  EXPECT_NEAR(j["up"]["delay_ms"]["p50"].get<double>(), 30.0, 0.2);
}

TEST(Link, DropsWhatIsNotIpv4) {
  Pair client, server;
  LinkConfig c;
  Link link(c, client.inner, server.inner);
  std::atomic<bool> stop{false};
  std::thread loop([&] { link.run(stop, std::chrono::steady_clock::now() + std::chrono::seconds(10)); });
  const std::uint8_t junk[40] = {0x60};
  ASSERT_GT(::write(client.outer, junk, sizeof junk), 0);
  EXPECT_FALSE(receive(server.outer, 200));
  stop = true;
  loop.join();
  EXPECT_EQ(link.counters().not_ipv4, 1u);
}

}  // namespace
}  // namespace throng::link
