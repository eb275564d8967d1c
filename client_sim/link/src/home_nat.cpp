#include "throng/link/home_nat.h"

namespace throng::link {

namespace {
constexpr auto kFragmentMemory = std::chrono::seconds(5);
}

HomeNat::HomeNat(NatConfig config, std::uint64_t seed) : config_(config), rng_(seed) {}

std::chrono::milliseconds HomeNat::timeout(std::uint8_t protocol) const {
  return protocol == static_cast<std::uint8_t>(Protocol::tcp) ? config_.tcp_timeout : config_.udp_timeout;
}

std::uint16_t HomeNat::draw_port(std::uint8_t protocol) {
  const std::uint32_t span = std::uint32_t{config_.last_port} - config_.first_port + 1;
  for (;;) {  // the range is far larger than any test's mappings
    const auto port = static_cast<std::uint16_t>(config_.first_port + rng_() % span);
    if (!by_public_.contains({protocol, port})) return port;
  }
}

void HomeNat::expire(Clock::time_point now) {
  if (now - last_expiry_ < std::chrono::milliseconds(200)) return;
  last_expiry_ = now;
  for (auto it = by_public_.begin(); it != by_public_.end();) {
    if (now - it->second.last_outbound > timeout(it->first.first)) {
      by_private_.erase(it->second.private_key);
      it = by_public_.erase(it);
      ++counters_.mappings_expired;
    } else {
      ++it;
    }
  }
  for (auto it = inbound_fragments_.begin(); it != inbound_fragments_.end();)
    it = now - it->second.second > kFragmentMemory ? inbound_fragments_.erase(it) : std::next(it);
}

NatVerdict HomeNat::outbound(std::span<std::uint8_t> packet, const PacketHeader& h, Clock::time_point now) {
  expire(now);
  if (h.protocol == Protocol::other) {
    ++counters_.unsupported;
    return NatVerdict::unsupported;
  }
  if (!h.first_fragment) {  // its ports were rewritten in the first fragment
    rewrite_source(packet, h, config_.public_address, 0);
    ++counters_.outbound;
    return NatVerdict::pass;
  }
  const std::uint8_t proto = h.raw_protocol;
  const PrivateKey key{proto, h.source, h.source_port};
  auto found = by_private_.find(key);
  if (found == by_private_.end()) {
    const PublicKey pub{proto, draw_port(proto)};
    Mapping m;
    m.private_key = key;
    m.public_port = pub.second;
    by_public_.emplace(pub, std::move(m));
    found = by_private_.emplace(key, pub).first;
    ++counters_.mappings_created;
  }
  Mapping& m = by_public_.at(found->second);
  m.contacted.insert({h.destination, h.destination_port});
  m.last_outbound = now;
  rewrite_source(packet, h, config_.public_address, m.public_port);
  ++counters_.outbound;
  return NatVerdict::pass;
}

NatVerdict HomeNat::inbound(std::span<std::uint8_t> packet, const PacketHeader& h, Clock::time_point now) {
  expire(now);
  if (h.destination != config_.public_address) {  // a private address is not routed on the internet
    ++counters_.unmapped;
    return NatVerdict::unmapped;
  }
  if (h.protocol == Protocol::other) {
    ++counters_.unsupported;
    return NatVerdict::unsupported;
  }
  if (!h.first_fragment) {
    const auto f = inbound_fragments_.find({h.source, h.identification});
    if (f == inbound_fragments_.end()) {
      ++counters_.unmapped;
      return NatVerdict::unmapped;
    }
    rewrite_destination(packet, h, f->second.first, 0);
    ++counters_.inbound;
    return NatVerdict::pass;
  }
  const auto it = by_public_.find({h.raw_protocol, h.destination_port});
  if (it == by_public_.end()) {
    ++counters_.unmapped;
    return NatVerdict::unmapped;
  }
  if (!it->second.contacted.contains({h.source, h.source_port})) {
    ++counters_.filtered;
    return NatVerdict::filtered;
  }
  const auto& [proto, address, port] = it->second.private_key;
  (void)proto;
  if (h.fragment) inbound_fragments_[{h.source, h.identification}] = {address, now};
  rewrite_destination(packet, h, address, port);
  ++counters_.inbound;
  return NatVerdict::pass;
}

}  // namespace throng::link
