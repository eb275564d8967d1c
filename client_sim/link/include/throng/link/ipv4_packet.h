#pragma once
// Reading and rewriting the IPv4, UDP and TCP headers of one packet in place, as a NAT does.
// Checksums are adjusted incrementally (RFC 1624): the first fragment of a fragmented datagram
// carries a UDP or TCP checksum over bytes that are not in it, so it cannot be recomputed there.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace throng::link {

enum class Protocol : std::uint8_t { other = 0, tcp = 6, udp = 17 };

// What a NAT needs to know of a packet. Addresses and ports in host byte order.
struct PacketHeader {
  std::uint32_t source = 0;
  std::uint32_t destination = 0;
  Protocol protocol = Protocol::other;
  std::uint8_t raw_protocol = 0;
  std::uint16_t source_port = 0;       // 0 for other protocols and for non-first fragments
  std::uint16_t destination_port = 0;
  std::uint16_t identification = 0;
  bool fragment = false;        // part of a fragmented datagram (more fragments follow, or offset > 0)
  bool first_fragment = true;   // offset 0: the transport header is here
  std::size_t header_bytes = 0;  // the IPv4 header's length
};

// The header of an IPv4 packet; nullopt when `packet` is not a well-formed IPv4 packet (version,
// header length, total length) or a first fragment too short for its UDP/TCP header.
std::optional<PacketHeader> parse_ipv4(std::span<const std::uint8_t> packet);

// Rewrite the source (or destination) address and port of a packet parse_ipv4 accepted, fixing
// the IPv4 header checksum and, where the packet holds it, the UDP/TCP checksum. A non-first
// fragment has no ports: only its address is rewritten.
void rewrite_source(std::span<std::uint8_t> packet, const PacketHeader& header, std::uint32_t address,
                    std::uint16_t port);
void rewrite_destination(std::span<std::uint8_t> packet, const PacketHeader& header, std::uint32_t address,
                         std::uint16_t port);

// The Internet checksum of the IPv4 header (0 when it is valid), and of a UDP/TCP segment with its
// pseudo-header (0 when valid): what tests check a rewritten packet with.
std::uint16_t ipv4_header_checksum(std::span<const std::uint8_t> packet);
std::uint16_t transport_checksum(std::span<const std::uint8_t> packet);

// "a.b.c.d" <-> host-order address; nullopt for anything else.
std::optional<std::uint32_t> parse_address(const std::string_view text);
std::string format_address(std::uint32_t address);

}  // namespace throng::link
