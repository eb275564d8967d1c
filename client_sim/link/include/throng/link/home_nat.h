#pragma once
// A home router's NAT, port-restricted cone (RFC 4787: endpoint-independent mapping,
// address-and-port-dependent filtering), for the hosts behind it:
//  - outbound: a private (address, port) gets one public port for every destination, chosen at
//    random (a game must not count on the port being kept);
//  - inbound: a datagram to a public port is let in only from an (address, port) the mapping has
//    sent to; anything else to the public address (no mapping, or an endpoint the host never
//    contacted) is dropped;
//  - a mapping expires after it has been idle outbound for the protocol's timeout, as real
//    routers do (UDP mappings last tens of seconds: a client must keep its mapping alive).
// Fragments: a non-first fragment has no ports. Outbound it takes the public address; inbound it
// is let in when the first fragment of the same datagram (same source and IP id) was.
#include <chrono>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <span>
#include <tuple>

#include "throng/link/ipv4_packet.h"

namespace throng::link {

struct NatConfig {
  std::uint32_t public_address = 0;
  std::chrono::milliseconds udp_timeout{30'000};
  std::chrono::milliseconds tcp_timeout{300'000};
  std::uint16_t first_port = 20000;  // public ports are drawn from [first_port, last_port]
  std::uint16_t last_port = 59999;
};

enum class NatVerdict : std::uint8_t {
  pass,
  unsupported,      // neither UDP nor TCP (ICMP, ...): a home NAT here keeps to the two
  unmapped,         // inbound: no mapping for that public port (or not to the public address)
  filtered,         // inbound: a mapping, but not from an endpoint it sent to
};

struct NatCounters {
  std::uint64_t mappings_created = 0;
  std::uint64_t mappings_expired = 0;
  std::uint64_t outbound = 0;
  std::uint64_t inbound = 0;
  std::uint64_t unmapped = 0;
  std::uint64_t filtered = 0;
  std::uint64_t unsupported = 0;
};

class HomeNat {
 public:
  using Clock = std::chrono::steady_clock;
  HomeNat(NatConfig config, std::uint64_t seed);

  // Rewrites a packet leaving the home network (source becomes the public address and port).
  NatVerdict outbound(std::span<std::uint8_t> packet, const PacketHeader& header, Clock::time_point now);
  // Rewrites a packet arriving at the public address (destination becomes the private host), or
  // says why it is dropped.
  NatVerdict inbound(std::span<std::uint8_t> packet, const PacketHeader& header, Clock::time_point now);

  const NatCounters& counters() const { return counters_; }
  std::size_t mappings() const { return by_public_.size(); }

 private:
  using Endpoint = std::pair<std::uint32_t, std::uint16_t>;  // address, port
  using PrivateKey = std::tuple<std::uint8_t, std::uint32_t, std::uint16_t>;  // protocol, address, port
  struct Mapping {
    PrivateKey private_key;
    std::uint16_t public_port = 0;
    std::set<Endpoint> contacted;
    Clock::time_point last_outbound;
  };
  using PublicKey = std::pair<std::uint8_t, std::uint16_t>;  // protocol, public port

  void expire(Clock::time_point now);
  std::chrono::milliseconds timeout(std::uint8_t protocol) const;
  std::uint16_t draw_port(std::uint8_t protocol);

  NatConfig config_;
  std::mt19937_64 rng_;
  std::map<PublicKey, Mapping> by_public_;
  std::map<PrivateKey, PublicKey> by_private_;
  // Inbound fragmented datagrams: (remote source, IP id) -> the private host their first fragment
  // went to, remembered for a few seconds.
  std::map<std::pair<std::uint32_t, std::uint16_t>, std::pair<std::uint32_t, Clock::time_point>> inbound_fragments_;
  Clock::time_point last_expiry_{};
  NatCounters counters_;
};

}  // namespace throng::link
