// The home NAT: port-restricted cone mapping, filtering, expiry, checksums kept valid.
#include <gtest/gtest.h>

#include "packet_builder.h"
#include "throng/link/home_nat.h"

namespace throng::link {
namespace {

using testing::ip;
using testing::make_packet;
using Clock = HomeNat::Clock;

NatConfig config() {
  NatConfig c;
  c.public_address = ip("10.77.0.100");
  c.udp_timeout = std::chrono::seconds(30);
  return c;
}

struct Sent {
  std::vector<std::uint8_t> packet;
  PacketHeader header;
};

Sent out(HomeNat& nat, std::uint8_t proto, std::uint16_t sport, const char* dst, std::uint16_t dport,
         Clock::time_point t) {
  Sent s{make_packet(proto, ip("10.77.1.2"), sport, ip(dst), dport), {}};
  EXPECT_EQ(nat.outbound(s.packet, *parse_ipv4(s.packet), t), NatVerdict::pass);
  s.header = *parse_ipv4(s.packet);
  return s;
}

NatVerdict in(HomeNat& nat, std::uint8_t proto, const char* src, std::uint16_t sport, std::uint32_t dst,
              std::uint16_t dport, Clock::time_point t, std::vector<std::uint8_t>* result = nullptr) {
  auto p = make_packet(proto, ip(src), sport, dst, dport);
  const NatVerdict v = nat.inbound(p, *parse_ipv4(p), t);
  if (result) *result = p;
  return v;
}

TEST(HomeNat, OutboundTakesThePublicAddressAndOnePortForEveryDestination) {
  HomeNat nat(config(), 1);
  const auto t = Clock::now();
  const Sent a = out(nat, 17, 5000, "10.77.0.1", 7400, t);
  EXPECT_EQ(a.header.source, ip("10.77.0.100"));
  EXPECT_GE(a.header.source_port, 20000);
  EXPECT_NE(a.header.source_port, 5000);  // a game must not count on the port being kept
  EXPECT_EQ(ipv4_header_checksum(a.packet), 0);
  EXPECT_EQ(transport_checksum(a.packet), 0);
  const Sent b = out(nat, 17, 5000, "10.77.0.1", 7401, t);  // another destination: the same mapping
  EXPECT_EQ(b.header.source_port, a.header.source_port);
  const Sent c = out(nat, 17, 5001, "10.77.0.1", 7400, t);  // another private port: another mapping
  EXPECT_NE(c.header.source_port, a.header.source_port);
  EXPECT_EQ(nat.counters().mappings_created, 2u);
}

TEST(HomeNat, InboundPassesOnlyFromAnEndpointTheMappingSentTo) {
  HomeNat nat(config(), 2);
  const auto t = Clock::now();
  const Sent a = out(nat, 17, 5000, "10.77.0.1", 7400, t);
  const std::uint32_t pub = ip("10.77.0.100");
  std::vector<std::uint8_t> back;
  ASSERT_EQ(in(nat, 17, "10.77.0.1", 7400, pub, a.header.source_port, t, &back), NatVerdict::pass);
  const PacketHeader h = *parse_ipv4(back);
  EXPECT_EQ(h.destination, ip("10.77.1.2"));
  EXPECT_EQ(h.destination_port, 5000);
  EXPECT_EQ(ipv4_header_checksum(back), 0);
  EXPECT_EQ(transport_checksum(back), 0);
  // The same host from another port: port-restricted, dropped.
  EXPECT_EQ(in(nat, 17, "10.77.0.1", 7401, pub, a.header.source_port, t), NatVerdict::filtered);
  // Another host: dropped.
  EXPECT_EQ(in(nat, 17, "10.77.0.9", 7400, pub, a.header.source_port, t), NatVerdict::filtered);
  // A port with no mapping, and the client's private address: dropped.
  EXPECT_EQ(in(nat, 17, "10.77.0.1", 7400, pub, static_cast<std::uint16_t>(a.header.source_port + 1), t),
            NatVerdict::unmapped);
  EXPECT_EQ(in(nat, 17, "10.77.0.1", 7400, ip("10.77.1.2"), 5000, t), NatVerdict::unmapped);
  // UDP and TCP mappings are apart.
  EXPECT_EQ(in(nat, 6, "10.77.0.1", 7400, pub, a.header.source_port, t), NatVerdict::unmapped);
  EXPECT_EQ(nat.counters().inbound, 1u);
  EXPECT_EQ(nat.counters().filtered, 2u);
  EXPECT_EQ(nat.counters().unmapped, 3u);
}

TEST(HomeNat, AMappingIdleOutboundForItsTimeoutExpires) {
  HomeNat nat(config(), 3);
  const auto t = Clock::now();
  const Sent a = out(nat, 17, 5000, "10.77.0.1", 7400, t);
  const std::uint32_t pub = ip("10.77.0.100");
  // Inbound traffic does not keep it alive.
  EXPECT_EQ(in(nat, 17, "10.77.0.1", 7400, pub, a.header.source_port, t + std::chrono::seconds(20)), NatVerdict::pass);
  EXPECT_EQ(in(nat, 17, "10.77.0.1", 7400, pub, a.header.source_port, t + std::chrono::seconds(31)),
            NatVerdict::unmapped);
  EXPECT_EQ(nat.counters().mappings_expired, 1u);
  // Outbound traffic does: a keepalive every 20 s holds it.
  const auto t2 = t + std::chrono::seconds(40);
  const Sent b = out(nat, 17, 5000, "10.77.0.1", 7400, t2);
  out(nat, 17, 5000, "10.77.0.1", 7400, t2 + std::chrono::seconds(20));
  EXPECT_EQ(in(nat, 17, "10.77.0.1", 7400, pub, b.header.source_port, t2 + std::chrono::seconds(45)), NatVerdict::pass);
}

TEST(HomeNat, TcpIsMappedAndOtherProtocolsAreNot) {
  HomeNat nat(config(), 4);
  const auto t = Clock::now();
  const Sent a = out(nat, 6, 40000, "10.77.0.1", 7400, t);
  EXPECT_EQ(transport_checksum(a.packet), 0);
  EXPECT_EQ(in(nat, 6, "10.77.0.1", 7400, ip("10.77.0.100"), a.header.source_port, t), NatVerdict::pass);
  auto icmp = make_packet(17, ip("10.77.1.2"), 1, ip("10.77.0.1"), 1);
  icmp[9] = 1;  // ICMP
  EXPECT_EQ(nat.outbound(icmp, *parse_ipv4(icmp), t), NatVerdict::unsupported);
}

TEST(HomeNat, FragmentsFollowTheirFirstFragment) {
  HomeNat nat(config(), 5);
  const auto t = Clock::now();
  const Sent a = out(nat, 17, 5000, "10.77.0.1", 7400, t);
  const std::uint32_t pub = ip("10.77.0.100");
  auto first = make_packet(17, ip("10.77.0.1"), 7400, pub, a.header.source_port, 64, 77);
  first[6] = 0x20;  // more fragments (the UDP checksum covers bytes not here: adjusted, not recomputed)
  ASSERT_EQ(nat.inbound(first, *parse_ipv4(first), t), NatVerdict::pass);
  auto rest = make_packet(17, ip("10.77.0.1"), 0, pub, 0, 64, 77);
  rest[7] = 0x10;  // offset 16 x 8 bytes
  rest[10] = rest[11] = 0;
  std::uint32_t s = 0;
  for (int i = 0; i < 20; i += 2) s += (rest[i] << 8) | rest[i + 1];
  const std::uint16_t sum = testing::fold_sum(s);
  rest[10] = static_cast<std::uint8_t>(sum >> 8);
  rest[11] = static_cast<std::uint8_t>(sum);
  ASSERT_EQ(nat.inbound(rest, *parse_ipv4(rest), t), NatVerdict::pass);
  EXPECT_EQ(parse_ipv4(rest)->destination, ip("10.77.1.2"));
  EXPECT_EQ(ipv4_header_checksum(rest), 0);
  auto stray = rest;
  stray[5] = 78;  // another datagram whose first fragment never came
  stray[10] = rest[10];
  EXPECT_NE(nat.inbound(stray, *parse_ipv4(stray), t), NatVerdict::pass);
}

TEST(Ipv4Packet, MalformedPacketsAreRefused) {
  auto p = make_packet(17, ip("1.2.3.4"), 1, ip("5.6.7.8"), 2);
  EXPECT_TRUE(parse_ipv4(p));
  EXPECT_FALSE(parse_ipv4(std::span<const std::uint8_t>(p.data(), 19)));
  auto v6 = p;
  v6[0] = 0x60;
  EXPECT_FALSE(parse_ipv4(v6));
  auto short_total = p;
  short_total[2] = 0x10;  // total length beyond the buffer
  EXPECT_FALSE(parse_ipv4(short_total));
  auto bad_ihl = p;
  bad_ihl[0] = 0x44;
  EXPECT_FALSE(parse_ipv4(bad_ihl));
}

}  // namespace
}  // namespace throng::link
