#pragma once
// A Fast DDS transport over UDP that reaches clients behind NAT (udp:// in --listen / --server).
//
// Stock UDP announces each participant's own interface addresses, which a client behind a home
// router cannot be reached at. Here every participant sends and receives on one UDP socket, and
// what it announces depends on its side:
//  - a server (bound to a known port) announces its public address and port ("direct" locators);
//  - a client announces no address at all, only a random 12-byte token. The server learns where a
//    token's datagrams come from (the NAT's public address and port) and replies there, from the
//    socket the client sent to, which is what a port-restricted NAT lets back in.
// Every datagram starts with a 24-byte header: magic, version, the logical channel it is for
// (Fast DDS's locator port: metatraffic or user data) and the sender's token; the RTPS message
// follows. So one socket carries every channel, and discovery, reliable topics and best-effort
// snapshots all cross the NAT on the mapping the client's first datagram made.
//
// A token's address is taken from the first datagram that names it and changes only after that
// address has been silent for kRebindAfter (a NAT that rebinds): a stranger who learns a token
// cannot redirect a live client's traffic. DDS Security, when on, still authenticates and
// encrypts everything above this layer.
#include <fastdds/rtps/transport/TransportDescriptorInterface.h>
#include <fastdds/rtps/transport/TransportInterface.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <thread>

#include <netinet/in.h>

namespace throng::protocol::dds_detail {

// Fast DDS picks a transport by locator kind. This transport borrows UDPv6's: the Debian build of
// Fast DDS 2.9.1 keeps its assertions, and one of them (ExternalLocatorsProcessor) aborts on a
// kind it does not know. A participant with this transport has no other, so no UDPv6 transport
// ever sees these locators; their addresses never start with 0xff, so none reads as multicast.
constexpr std::int32_t kNatUdpLocatorKind = LOCATOR_KIND_UDPv6;
// The largest RTPS message handed to the socket: with the header, IPv4 and UDP it stays under a
// 1500-byte MTU, so no datagram is fragmented by IP (one lost fragment would lose it whole).
constexpr std::uint32_t kNatUdpMaxMessage = 1400;
constexpr std::size_t kNatUdpHeaderBytes = 24;

struct NatUdpTransportDescriptor final : eprosima::fastdds::rtps::TransportDescriptorInterface {
  NatUdpTransportDescriptor() : TransportDescriptorInterface(kNatUdpMaxMessage, 4) {}
  eprosima::fastdds::rtps::TransportInterface* create_transport() const override;
  std::uint32_t min_send_buffer_size() const override { return kNatUdpMaxMessage; }

  // Server side: the address and port bound (0.0.0.0 = every interface) and the public address
  // announced to clients. Client side: bind_port 0 (any), no public address.
  std::uint32_t bind_address = 0;  // host order
  std::uint16_t bind_port = 0;
  std::uint32_t public_address = 0;
  std::uint16_t public_port = 0;
  bool server() const { return bind_port != 0; }
};

// A direct locator for ADDRESS:PORT (the server's), with logical channel `channel` (0: Fast DDS
// fills in the well-known port of participants 0..3, as for a UDP initial peer).
eprosima::fastrtps::rtps::Locator_t nat_udp_direct_locator(std::uint32_t address, std::uint16_t port,
                                                           std::uint32_t channel);

class NatUdpTransport final : public eprosima::fastdds::rtps::TransportInterface {
 public:
  using Locator = eprosima::fastrtps::rtps::Locator_t;
  using Receiver = eprosima::fastdds::rtps::TransportReceiverInterface;
  static constexpr auto kRebindAfter = std::chrono::seconds(10);

  explicit NatUdpTransport(const NatUdpTransportDescriptor& descriptor);
  ~NatUdpTransport() override;

  bool init(const eprosima::fastrtps::rtps::PropertyPolicy* properties = nullptr) override;
  bool IsInputChannelOpen(const Locator& locator) const override;
  bool IsLocatorSupported(const Locator& locator) const override { return locator.kind == kNatUdpLocatorKind; }
  bool is_locator_allowed(const Locator& locator) const override { return IsLocatorSupported(locator); }
  Locator RemoteToMainLocal(const Locator& remote) const override;
  bool transform_remote_locator(const Locator& remote, Locator& result) const override;
  bool OpenOutputChannel(eprosima::fastdds::rtps::SendResourceList& list, const Locator& locator) override;
  bool OpenInputChannel(const Locator& locator, Receiver* receiver, std::uint32_t max_message_size) override;
  bool CloseInputChannel(const Locator& locator) override;
  bool DoInputLocatorsMatch(const Locator& a, const Locator& b) const override;
  eprosima::fastdds::rtps::LocatorList NormalizeLocator(const Locator& locator) override;
  void select_locators(eprosima::fastrtps::rtps::LocatorSelector& selector) const override;
  bool is_local_locator(const Locator& locator) const override;
  eprosima::fastdds::rtps::TransportDescriptorInterface* get_configuration() override { return &descriptor_; }
  void AddDefaultOutputLocator(eprosima::fastdds::rtps::LocatorList&) override {}
  bool getDefaultMetatrafficMulticastLocators(eprosima::fastdds::rtps::LocatorList&, std::uint32_t) const override {
    return true;  // no multicast: nothing to add
  }
  bool getDefaultMetatrafficUnicastLocators(eprosima::fastdds::rtps::LocatorList& locators,
                                            std::uint32_t port) const override;
  bool getDefaultUnicastLocators(eprosima::fastdds::rtps::LocatorList& locators, std::uint32_t port) const override;
  bool fillMetatrafficMulticastLocator(Locator&, std::uint32_t) const override { return true; }
  bool fillMetatrafficUnicastLocator(Locator& locator, std::uint32_t port) const override;
  bool configureInitialPeerLocator(Locator& locator, const eprosima::fastrtps::rtps::PortParameters& params,
                                   std::uint32_t domain_id, eprosima::fastdds::rtps::LocatorList& list) const override;
  bool fillUnicastLocator(Locator& locator, std::uint32_t port) const override;
  std::uint32_t max_recv_buffer_size() const override { return 65536; }
  void shutdown() override;

  // Sends one RTPS message to every locator of this kind in [begin, end).
  bool send(const std::uint8_t* data, std::uint32_t size, eprosima::fastdds::rtps::LocatorsIterator* begin,
            eprosima::fastdds::rtps::LocatorsIterator* end);

 private:
  using Token = std::array<std::uint8_t, 12>;
  struct Learned {
    sockaddr_in address{};
    std::chrono::steady_clock::time_point last_heard;
  };

  Locator self_locator(std::uint32_t channel) const;
  void receive_loop();
  void learn(const Token& token, const sockaddr_in& from);
  bool destination(const Locator& locator, sockaddr_in& out) const;

  NatUdpTransportDescriptor descriptor_;
  Token token_{};
  int socket_ = -1;
  int wake_ = -1;  // eventfd: ends the receive loop
  std::thread receiver_thread_;
  std::atomic<bool> stopping_{false};

  mutable std::shared_mutex channels_mutex_;
  std::map<std::uint32_t, Receiver*> channels_;  // logical channel -> Fast DDS's receiver

  mutable std::shared_mutex learned_mutex_;
  std::map<Token, Learned> learned_;
};

}  // namespace throng::protocol::dds_detail
