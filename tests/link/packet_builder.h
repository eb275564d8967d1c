#pragma once
// Hand-made IPv4 packets with valid checksums, for the link's tests.
#include <cstdint>
#include <vector>

#include "throng/link/ipv4_packet.h"

namespace throng::link::testing {

inline std::uint16_t fold_sum(std::uint32_t s) {
  while (s >> 16) s = (s & 0xffff) + (s >> 16);
  return static_cast<std::uint16_t>(~s);
}

// A UDP (proto 17) or TCP (6) packet from src:sport to dst:dport with `payload` bytes.
inline std::vector<std::uint8_t> make_packet(std::uint8_t proto, std::uint32_t src, std::uint16_t sport,
                                             std::uint32_t dst, std::uint16_t dport, std::size_t payload = 32,
                                             std::uint16_t ip_id = 1) {
  const std::size_t th = proto == 6 ? 20 : 8;
  std::vector<std::uint8_t> p(20 + th + payload, 0);
  auto w16 = [&](std::size_t at, std::uint32_t v) {
    p[at] = static_cast<std::uint8_t>(v >> 8);
    p[at + 1] = static_cast<std::uint8_t>(v);
  };
  auto w32 = [&](std::size_t at, std::uint32_t v) {
    w16(at, v >> 16);
    w16(at + 2, v & 0xffff);
  };
  p[0] = 0x45;
  w16(2, static_cast<std::uint32_t>(p.size()));
  w16(4, ip_id);
  p[8] = 64;
  p[9] = proto;
  w32(12, src);
  w32(16, dst);
  for (std::size_t i = 0; i < payload; ++i) p[20 + th + i] = static_cast<std::uint8_t>(i * 7 + 3);
  w16(20, sport);
  w16(22, dport);
  if (proto == 17) w16(24, static_cast<std::uint32_t>(th + payload));
  if (proto == 6) p[32] = 0x50;  // data offset 5 words
  std::uint32_t s = 0;
  for (std::size_t i = 0; i < 20; i += 2) s += (p[i] << 8) | p[i + 1];
  w16(10, fold_sum(s));
  const std::size_t len = th + payload;
  s = 0;
  for (std::size_t i = 12; i < 20; i += 2) s += (p[i] << 8) | p[i + 1];
  s += proto + static_cast<std::uint32_t>(len);
  for (std::size_t i = 0; i < len; i += 2) s += (p[20 + i] << 8) | (i + 1 < len ? p[20 + i + 1] : 0);
  w16(20 + (proto == 6 ? 16 : 6), fold_sum(s));
  return p;
}

inline std::uint32_t ip(const char* text) { return *parse_address(std::string_view(text)); }

}  // namespace throng::link::testing
