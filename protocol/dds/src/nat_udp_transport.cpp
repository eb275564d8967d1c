#include "nat_udp_transport.h"

#include <fastdds/rtps/common/LocatorSelector.hpp>
#include <fastdds/rtps/common/LocatorSelectorEntry.hpp>
#include <fastdds/rtps/network/SenderResource.h>

#include <arpa/inet.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/random.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <vector>

namespace throng::protocol::dds_detail {

namespace rtps = eprosima::fastdds::rtps;
using eprosima::fastrtps::rtps::Locator_t;
using eprosima::fastdds::rtps::LocatorList;

namespace {

constexpr std::uint8_t kMagic[4] = {'T', 'H', 'N', 'U'};
constexpr std::uint8_t kVersion = 1;
constexpr std::uint8_t kFlagFragment = 1;
// Bounds on messages in pieces: a sender cannot make the receiver hold more than this.
constexpr std::size_t kMaxPieces = (kNatUdpMaxMessage + kNatUdpFragmentPayload - 1) / kNatUdpFragmentPayload;
constexpr std::size_t kMaxPartials = 256;
constexpr std::size_t kMaxPartialsPerSource = 8;
constexpr auto kPartialLifetime = std::chrono::seconds(2);
// A token not heard from for this long is forgotten (a client that left; a stranger's invention).
constexpr auto kForgetAfter = std::chrono::seconds(60);
// Datagrams handled between two looks at the stop flag and the expiry sweeps.
constexpr int kBatch = 64;
// Locator address byte 0: what the rest of the address holds.
constexpr std::uint8_t kDirect = 1;  // bytes 10-11 UDP port, 12-15 IPv4 address (network order)
constexpr std::uint8_t kToken = 2;   // bytes 4-15 the client's token

void put32(std::uint8_t* p, std::uint32_t v) {
  p[0] = static_cast<std::uint8_t>(v >> 24);
  p[1] = static_cast<std::uint8_t>(v >> 16);
  p[2] = static_cast<std::uint8_t>(v >> 8);
  p[3] = static_cast<std::uint8_t>(v);
}
std::uint32_t get32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

// One sender per transport: every send goes out of the transport's one socket.
class NatUdpSender final : public eprosima::fastrtps::rtps::SenderResource {
 public:
  explicit NatUdpSender(NatUdpTransport& transport) : SenderResource(transport.kind()) {
    send_lambda_ = [&transport](const eprosima::fastrtps::rtps::octet* data, std::uint32_t size,
                                rtps::LocatorsIterator* begin, rtps::LocatorsIterator* end,
                                const std::chrono::steady_clock::time_point&) {
      return transport.send(data, size, begin, end);
    };
  }
};

// A client's locator: its token, no address.
Locator_t token_locator(const std::array<std::uint8_t, 12>& token, std::uint32_t channel) {
  Locator_t l;
  l.kind = kNatUdpLocatorKind;
  l.port = channel;
  std::memset(l.address, 0, sizeof l.address);
  l.address[0] = kToken;
  std::memcpy(l.address + 4, token.data(), token.size());
  return l;
}

}  // namespace

Locator_t nat_udp_direct_locator(std::uint32_t address, std::uint16_t port, std::uint32_t channel) {
  Locator_t l;
  l.kind = kNatUdpLocatorKind;
  l.port = channel;
  std::memset(l.address, 0, sizeof l.address);
  l.address[0] = kDirect;
  l.address[10] = static_cast<std::uint8_t>(port >> 8);
  l.address[11] = static_cast<std::uint8_t>(port);
  put32(l.address + 12, address);
  return l;
}

rtps::TransportInterface* NatUdpTransportDescriptor::create_transport() const { return new NatUdpTransport(*this); }

NatUdpTransport::NatUdpTransport(const NatUdpTransportDescriptor& descriptor)
    : TransportInterface(kNatUdpLocatorKind), descriptor_(descriptor) {}

// The descriptors live as long as the transport: Fast DDS calls shutdown() before it deletes the
// builtin protocols, whose last act is the participant's dispose announcement, sent through this
// socket. Fast DDS drops its senders and receivers before the transport itself.
NatUdpTransport::~NatUdpTransport() {
  shutdown();
  if (socket_ >= 0) ::close(socket_);
  if (wake_ >= 0) ::close(wake_);
}

bool NatUdpTransport::init(const eprosima::fastrtps::rtps::PropertyPolicy*) {
  if (::getrandom(token_.data(), token_.size(), 0) != static_cast<ssize_t>(token_.size())) return false;
  socket_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (socket_ < 0) return false;
  // Bursts of snapshots and fragments of a reliable sync: room for them in the kernel.
  const int buffer = 4 << 20;
  (void)::setsockopt(socket_, SOL_SOCKET, SO_RCVBUF, &buffer, sizeof buffer);
  (void)::setsockopt(socket_, SOL_SOCKET, SO_SNDBUF, &buffer, sizeof buffer);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(descriptor_.bind_port);
  a.sin_addr.s_addr = htonl(descriptor_.bind_address);
  if (::bind(socket_, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {  // create_participant said why
    ::close(socket_);
    socket_ = -1;
    return false;
  }
  wake_ = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
  if (wake_ < 0) return false;
  receiver_thread_ = std::thread([this] { receive_loop(); });
  return true;
}

void NatUdpTransport::shutdown() {
  if (stopping_.exchange(true)) return;
  if (wake_ >= 0) {
    const std::uint64_t one = 1;
    (void)::write(wake_, &one, sizeof one);
  }
  if (receiver_thread_.joinable()) receiver_thread_.join();
}

Locator_t NatUdpTransport::self_locator(std::uint32_t channel) const {
  if (descriptor_.server())
    return nat_udp_direct_locator(descriptor_.public_address, descriptor_.public_port, channel);
  return token_locator(token_, channel);
}

bool NatUdpTransport::IsInputChannelOpen(const Locator& locator) const {
  std::shared_lock lock(channels_mutex_);
  return IsLocatorSupported(locator) && channels_.contains(locator.port);
}

NatUdpTransport::Locator NatUdpTransport::RemoteToMainLocal(const Locator& remote) const {
  Locator l(remote);
  l.set_Invalid_Address();
  return l;
}

bool NatUdpTransport::transform_remote_locator(const Locator& remote, Locator& result) const {
  if (!IsLocatorSupported(remote)) return false;
  result = remote;
  return true;
}

bool NatUdpTransport::OpenOutputChannel(rtps::SendResourceList& list, const Locator& locator) {
  if (!IsLocatorSupported(locator)) return false;
  for (const auto& sender : list)
    if (sender->kind() == kind()) return true;
  list.emplace_back(std::make_unique<NatUdpSender>(*this));
  return true;
}

bool NatUdpTransport::OpenInputChannel(const Locator& locator, Receiver* receiver, std::uint32_t) {
  if (!IsLocatorSupported(locator) || socket_ < 0) return false;
  std::unique_lock lock(channels_mutex_);
  if (!first_channel_) first_channel_ = locator.port;
  return channels_.emplace(locator.port, receiver).second;
}

bool NatUdpTransport::CloseInputChannel(const Locator& locator) {
  // Under the lock the receive loop holds while it delivers: once this returns, the receiver
  // (which Fast DDS is about to delete) is never called again.
  std::unique_lock lock(channels_mutex_);
  return channels_.erase(locator.port) > 0;
}

bool NatUdpTransport::DoInputLocatorsMatch(const Locator& a, const Locator& b) const {
  return a.kind == b.kind && a.port == b.port;
}

LocatorList NatUdpTransport::NormalizeLocator(const Locator& locator) {
  LocatorList list;
  list.push_back(locator);
  return list;
}

void NatUdpTransport::select_locators(eprosima::fastrtps::rtps::LocatorSelector& selector) const {
  auto& entries = selector.transport_starts();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    auto* entry = entries[i];
    if (!entry->transport_should_process) continue;
    bool selected = false;
    for (std::size_t j = 0; j < entry->unicast.size(); ++j) {
      if (IsLocatorSupported(entry->unicast[j]) && !selector.is_selected(entry->unicast[j])) {
        entry->state.unicast.push_back(j);
        selected = true;
      }
    }
    if (selected) selector.select(i);
  }
}

bool NatUdpTransport::is_local_locator(const Locator& locator) const {
  if (!IsLocatorSupported(locator) || locator.address[0] != kToken) return false;
  return std::memcmp(locator.address + 4, token_.data(), token_.size()) == 0;
}

bool NatUdpTransport::getDefaultMetatrafficUnicastLocators(LocatorList& locators, std::uint32_t port) const {
  locators.push_back(self_locator(port));
  return true;
}

bool NatUdpTransport::getDefaultUnicastLocators(LocatorList& locators, std::uint32_t port) const {
  locators.push_back(self_locator(port));
  return true;
}

bool NatUdpTransport::fillMetatrafficUnicastLocator(Locator& locator, std::uint32_t port) const {
  if (locator.port == 0) locator.port = port;
  return true;
}

bool NatUdpTransport::fillUnicastLocator(Locator& locator, std::uint32_t port) const {
  if (locator.port == 0) locator.port = port;
  return true;
}

bool NatUdpTransport::configureInitialPeerLocator(Locator& locator,
                                                  const eprosima::fastrtps::rtps::PortParameters& params,
                                                  std::uint32_t domain_id, LocatorList& list) const {
  if (locator.port != 0) {
    list.push_back(locator);
    return true;
  }
  for (std::uint32_t i = 0; i < descriptor_.maxInitialPeersRange; ++i) {
    Locator l(locator);
    l.port = params.getUnicastPort(domain_id, i);
    list.push_back(l);
  }
  return true;
}

bool NatUdpTransport::destination(const Locator& locator, sockaddr_in& out) const {
  out = {};
  out.sin_family = AF_INET;
  if (locator.address[0] == kDirect) {
    out.sin_port = htons(static_cast<std::uint16_t>((locator.address[10] << 8) | locator.address[11]));
    out.sin_addr.s_addr = htonl(get32(locator.address + 12));
    return out.sin_port != 0;
  }
  if (locator.address[0] != kToken) return false;
  Token token;
  std::memcpy(token.data(), locator.address + 4, token.size());
  std::shared_lock lock(learned_mutex_);
  const auto it = learned_.find(token);
  if (it == learned_.end()) return false;  // never heard from: no address to reach it at
  out = it->second.address;
  return true;
}

bool NatUdpTransport::send(const std::uint8_t* data, std::uint32_t size, rtps::LocatorsIterator* begin,
                           rtps::LocatorsIterator* end) {
  if (socket_ < 0 || size > kNatUdpMaxMessage) return false;
  std::uint8_t buffer[kNatUdpFragmentHeaderBytes + kNatUdpDatagramPayload];
  std::memcpy(buffer, kMagic, 4);
  buffer[4] = kVersion;
  buffer[6] = buffer[7] = 0;
  std::memcpy(buffer + 12, token_.data(), token_.size());
  const bool whole = size <= kNatUdpDatagramPayload;
  const std::size_t pieces = whole ? 1 : (size + kNatUdpFragmentPayload - 1) / kNatUdpFragmentPayload;
  const std::uint32_t id = whole ? 0 : next_message_id_.fetch_add(1);
  bool ok = true;
  for (rtps::LocatorsIterator& it = *begin; it != *end; ++it) {
    const Locator& l = *it;
    if (!IsLocatorSupported(l)) continue;
    sockaddr_in to;
    if (!destination(l, to)) continue;
    put32(buffer + 8, l.port);
    for (std::size_t i = 0; i < pieces; ++i) {
      std::size_t header = kNatUdpHeaderBytes, from = 0, n = size;
      buffer[5] = 0;
      if (!whole) {
        buffer[5] = kFlagFragment;
        put32(buffer + 24, id);
        buffer[28] = static_cast<std::uint8_t>(i >> 8);
        buffer[29] = static_cast<std::uint8_t>(i);
        buffer[30] = static_cast<std::uint8_t>(pieces >> 8);
        buffer[31] = static_cast<std::uint8_t>(pieces);
        header = kNatUdpFragmentHeaderBytes;
        from = i * kNatUdpFragmentPayload;
        n = std::min(kNatUdpFragmentPayload, size - from);
      }
      std::memcpy(buffer + header, data + from, n);
      const ssize_t sent = ::sendto(socket_, buffer, header + n, MSG_DONTWAIT, reinterpret_cast<const sockaddr*>(&to),
                                    sizeof to);
      // A full socket buffer drops the datagram, as a congested router would: best-effort data
      // is superseded and reliable data is repaired by its protocol.
      if (sent < 0 && errno != EAGAIN && errno != EWOULDBLOCK) ok = false;
    }
  }
  return ok;
}

void NatUdpTransport::learn(const Token& token, const sockaddr_in& from) {
  const auto now = std::chrono::steady_clock::now();
  {
    std::shared_lock lock(learned_mutex_);
    const auto it = learned_.find(token);
    if (it != learned_.end() && it->second.address.sin_addr.s_addr == from.sin_addr.s_addr &&
        it->second.address.sin_port == from.sin_port && now - it->second.last_heard < std::chrono::seconds(1))
      return;  // the common case: nothing changes
  }
  std::unique_lock lock(learned_mutex_);
  Learned& l = learned_[token];
  const bool same = l.address.sin_addr.s_addr == from.sin_addr.s_addr && l.address.sin_port == from.sin_port;
  if (same || l.address.sin_family == 0 || now - l.last_heard > kRebindAfter) {
    l.address = from;
    l.last_heard = now;
  }
}

void NatUdpTransport::receive_loop() {
  std::vector<std::uint8_t> buffer(65536);
  while (!stopping_.load()) {
    pollfd fds[2] = {{socket_, POLLIN, 0}, {wake_, POLLIN, 0}};
    if (::poll(fds, 2, 1000) <= 0) continue;
    if (fds[1].revents != 0) break;
    for (int batch = 0; batch < kBatch && !stopping_.load(); ++batch) {
      sockaddr_in from{};
      socklen_t from_len = sizeof from;
      const ssize_t n = ::recvfrom(socket_, buffer.data(), buffer.size(), MSG_DONTWAIT,
                                   reinterpret_cast<sockaddr*>(&from), &from_len);
      if (n < 0) break;
      if (static_cast<std::size_t>(n) < kNatUdpHeaderBytes + 1 || std::memcmp(buffer.data(), kMagic, 4) != 0 ||
          buffer[4] != kVersion)
        continue;  // not ours
      Token token;
      std::memcpy(token.data(), buffer.data() + 12, token.size());
      if (token == token_) continue;  // our own datagram, looped back
      if (buffer[5] & kFlagFragment) {
        reassemble(token, from, buffer.data(), static_cast<std::size_t>(n));
      } else {
        deliver(token, from, get32(buffer.data() + 8), buffer.data() + kNatUdpHeaderBytes,
                static_cast<std::size_t>(n) - kNatUdpHeaderBytes);
      }
    }
    const auto now = std::chrono::steady_clock::now();
    if (now - last_expiry_ > std::chrono::milliseconds(200)) {
      last_expiry_ = now;
      for (auto it = partial_.begin(); it != partial_.end();)
        it = now - it->second.first > kPartialLifetime ? partial_.erase(it) : std::next(it);
      std::unique_lock lock(learned_mutex_);
      for (auto it = learned_.begin(); it != learned_.end();)
        it = now - it->second.last_heard > kForgetAfter ? learned_.erase(it) : std::next(it);
    }
  }
}

void NatUdpTransport::reassemble(const Token& token, const sockaddr_in& from, const std::uint8_t* d, std::size_t n) {
  if (n <= kNatUdpFragmentHeaderBytes) return;
  const std::uint32_t id = get32(d + 24);
  const std::size_t index = (std::size_t{d[28]} << 8) | d[29];
  const std::size_t count = (std::size_t{d[30]} << 8) | d[31];
  const std::size_t len = n - kNatUdpFragmentHeaderBytes;
  const std::uint32_t channel = get32(d + 8);
  // Every piece but the last is full; a count that could not have been sent is not ours.
  if (count < 2 || count > kMaxPieces || index >= count || len > kNatUdpFragmentPayload ||
      (index + 1 < count && len != kNatUdpFragmentPayload))
    return;
  // Keyed by the source too: nobody who knows a token can break up another sender's messages.
  const PartialKey key{from.sin_addr.s_addr, from.sin_port, token, id};
  auto it = partial_.find(key);
  if (it == partial_.end()) {
    // Each source may have a few messages under way; a full table gives up its oldest, so a
    // flood of beginnings from strangers cannot keep a real handshake out.
    std::size_t mine = 0;
    auto oldest = partial_.end();
    for (auto p = partial_.begin(); p != partial_.end(); ++p) {
      if (p->first.address == key.address && p->first.port == key.port) ++mine;
      if (oldest == partial_.end() || p->second.first < oldest->second.first) oldest = p;
    }
    if (mine >= kMaxPartialsPerSource) return;
    if (partial_.size() >= kMaxPartials) partial_.erase(oldest);
    Partial p;
    p.bytes.resize(count * kNatUdpFragmentPayload);
    p.have.assign(count, false);
    p.channel = channel;
    p.first = std::chrono::steady_clock::now();
    it = partial_.emplace(key, std::move(p)).first;
  }
  Partial& p = it->second;
  if (p.have.size() != count || p.channel != channel) {  // pieces that disagree: drop the message
    partial_.erase(it);
    return;
  }
  if (p.have[index]) return;
  p.have[index] = true;
  ++p.received;
  std::memcpy(p.bytes.data() + index * kNatUdpFragmentPayload, d + kNatUdpFragmentHeaderBytes, len);
  if (index + 1 == count) p.size = index * kNatUdpFragmentPayload + len;
  if (p.received < count) return;
  Partial whole = std::move(p);
  partial_.erase(it);
  deliver(token, from, channel, whole.bytes.data(), whole.size);
}

void NatUdpTransport::deliver(const Token& token, const sockaddr_in& from, std::uint32_t channel,
                              const std::uint8_t* data, std::size_t size) {
  // Not an RTPS message: dropped before anything is learned from it.
  if (size < 20 || std::memcmp(data, "RTPS", 4) != 0) return;
  learn(token, from);
  std::shared_lock lock(channels_mutex_);
  auto it = channels_.find(channel);
  if (it == channels_.end() && channel == kNatUdpServerDiscoveryChannel && first_channel_)
    it = channels_.find(*first_channel_);
  if (it == channels_.end()) return;  // a channel this participant does not have
  it->second->OnDataReceived(data, static_cast<std::uint32_t>(size), self_locator(it->first),
                             token_locator(token, channel));
}

}  // namespace throng::protocol::dds_detail
