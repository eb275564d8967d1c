#include "throng/link/ipv4_packet.h"

#include <arpa/inet.h>

namespace throng::link {

namespace {

std::uint16_t read16(const std::uint8_t* p) { return static_cast<std::uint16_t>((p[0] << 8) | p[1]); }
std::uint32_t read32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}
void write16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v >> 8);
  p[1] = static_cast<std::uint8_t>(v);
}
void write32(std::uint8_t* p, std::uint32_t v) {
  write16(p, static_cast<std::uint16_t>(v >> 16));
  write16(p + 2, static_cast<std::uint16_t>(v));
}

// RFC 1624 eqn. 3: HC' = ~(~HC + ~m + m'), one 16-bit word at a time.
std::uint16_t adjust(std::uint16_t sum, std::uint16_t old_word, std::uint16_t new_word) {
  std::uint32_t s = static_cast<std::uint16_t>(~sum);
  s += static_cast<std::uint16_t>(~old_word);
  s += new_word;
  while (s >> 16) s = (s & 0xffff) + (s >> 16);
  return static_cast<std::uint16_t>(~s);
}
std::uint16_t adjust32(std::uint16_t sum, std::uint32_t old_value, std::uint32_t new_value) {
  sum = adjust(sum, static_cast<std::uint16_t>(old_value >> 16), static_cast<std::uint16_t>(new_value >> 16));
  return adjust(sum, static_cast<std::uint16_t>(old_value), static_cast<std::uint16_t>(new_value));
}

std::uint32_t ones_sum(const std::uint8_t* p, std::size_t n, std::uint32_t s = 0) {
  for (std::size_t i = 0; i + 1 < n; i += 2) s += read16(p + i);
  if (n % 2 == 1) s += std::uint32_t{p[n - 1]} << 8;
  return s;
}
std::uint16_t fold(std::uint32_t s) {
  while (s >> 16) s = (s & 0xffff) + (s >> 16);
  return static_cast<std::uint16_t>(~s);
}

// Where the transport checksum sits in the segment (UDP 6, TCP 16).
std::size_t checksum_offset(Protocol p) { return p == Protocol::udp ? 6 : 16; }

// address_at: 12 (source) or 16 (destination); port_at: 0 or 2 within the transport header.
void rewrite(std::span<std::uint8_t> packet, const PacketHeader& h, std::size_t address_at, std::size_t port_at,
             std::uint32_t address, std::uint16_t port) {
  std::uint8_t* ip = packet.data();
  const std::uint32_t old_address = read32(ip + address_at);
  write32(ip + address_at, address);
  write16(ip + 10, adjust32(read16(ip + 10), old_address, address));
  if (h.protocol == Protocol::other || !h.first_fragment) return;
  std::uint8_t* seg = ip + h.header_bytes;
  std::uint8_t* sum_at = seg + checksum_offset(h.protocol);
  const std::uint16_t old_port = read16(seg + port_at);
  write16(seg + port_at, port);
  std::uint16_t sum = read16(sum_at);
  if (h.protocol == Protocol::udp && sum == 0) return;  // UDP sent without a checksum keeps none
  sum = adjust(adjust32(sum, old_address, address), old_port, port);
  if (h.protocol == Protocol::udp && sum == 0) sum = 0xffff;  // 0 would mean "no checksum"
  write16(sum_at, sum);
}

}  // namespace

std::optional<PacketHeader> parse_ipv4(std::span<const std::uint8_t> packet) {
  if (packet.size() < 20) return std::nullopt;
  const std::uint8_t* ip = packet.data();
  if ((ip[0] >> 4) != 4) return std::nullopt;
  PacketHeader h;
  h.header_bytes = std::size_t{ip[0] & 0x0fu} * 4;
  const std::size_t total = read16(ip + 2);
  if (h.header_bytes < 20 || total < h.header_bytes || total > packet.size()) return std::nullopt;
  h.identification = read16(ip + 4);
  const std::uint16_t flags_offset = read16(ip + 6);
  const bool more = (flags_offset & 0x2000) != 0;
  const std::uint16_t offset = flags_offset & 0x1fff;
  h.fragment = more || offset != 0;
  h.first_fragment = offset == 0;
  h.raw_protocol = ip[9];
  h.protocol = ip[9] == 6 ? Protocol::tcp : ip[9] == 17 ? Protocol::udp : Protocol::other;
  h.source = read32(ip + 12);
  h.destination = read32(ip + 16);
  if (h.protocol != Protocol::other && h.first_fragment) {
    const std::size_t need = h.protocol == Protocol::udp ? 8 : 20;
    if (total - h.header_bytes < need) return std::nullopt;
    h.source_port = read16(ip + h.header_bytes);
    h.destination_port = read16(ip + h.header_bytes + 2);
  }
  return h;
}

void rewrite_source(std::span<std::uint8_t> packet, const PacketHeader& header, std::uint32_t address,
                    std::uint16_t port) {
  rewrite(packet, header, 12, 0, address, port);
}

void rewrite_destination(std::span<std::uint8_t> packet, const PacketHeader& header, std::uint32_t address,
                         std::uint16_t port) {
  rewrite(packet, header, 16, 2, address, port);
}

std::uint16_t ipv4_header_checksum(std::span<const std::uint8_t> packet) {
  return fold(ones_sum(packet.data(), std::size_t{packet[0] & 0x0fu} * 4));
}

std::uint16_t transport_checksum(std::span<const std::uint8_t> packet) {
  const std::uint8_t* ip = packet.data();
  const std::size_t hl = std::size_t{ip[0] & 0x0fu} * 4;
  const std::size_t total = read16(ip + 2);
  const std::size_t len = total - hl;
  std::uint32_t s = ones_sum(ip + 12, 8);  // pseudo-header: source, destination
  s += ip[9];
  s += static_cast<std::uint32_t>(len);
  return fold(ones_sum(ip + hl, len, s));
}

std::optional<std::uint32_t> parse_address(std::string_view text) {
  const std::string s(text);
  in_addr a{};
  if (::inet_pton(AF_INET, s.c_str(), &a) != 1) return std::nullopt;
  return ntohl(a.s_addr);
}

std::string format_address(std::uint32_t address) {
  in_addr a{};
  a.s_addr = htonl(address);
  char text[INET_ADDRSTRLEN] = {};
  ::inet_ntop(AF_INET, &a, text, sizeof text);
  return text;
}

}  // namespace throng::link
