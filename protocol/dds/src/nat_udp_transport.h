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
// follows. A message longer than one datagram carries (DDS Security's handshake holds
// certificates and a permissions document of several kB) is cut into datagrams of its own here,
// with 8 more header bytes (message id, index, count), and put back together by the receiver:
// IP never fragments, which many NATs and load balancers drop. So one socket carries every channel, and discovery, reliable topics and best-effort
// snapshots all cross the NAT on the mapping the client's first datagram made.
//
// A token's address is taken from the first datagram that names it and changes only after that
// address has been silent for kRebindAfter (a NAT that rebinds): a stranger off the client's path
// cannot redirect a live client's traffic. The token travels in clear, so an observer on the
// path (shared Wi-Fi) who outlasts a client's silence can: with DDS Security that denies service,
// it cannot read or forge the match (authentication and encryption sit above this layer).
#include <fastdds/rtps/transport/TransportDescriptorInterface.h>
#include <fastdds/rtps/transport/TransportInterface.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>
#include <thread>
#include <vector>

#include <netinet/in.h>

namespace throng::protocol::dds_detail {

// Fast DDS picks a transport by locator kind. This transport borrows UDPv6's: the Debian build of
// Fast DDS 2.9.1 keeps its assertions, and one of them (ExternalLocatorsProcessor) aborts on a
// kind it does not know. A participant with this transport has no other, so no UDPv6 transport
// ever sees these locators; their addresses never start with 0xff, so none reads as multicast.
constexpr std::int32_t kNatUdpLocatorKind = LOCATOR_KIND_UDPv6;
// The largest RTPS message Fast DDS hands this transport: room for the security handshake. Fast
// DDS cuts larger samples into RTPS fragments itself, each repaired on its own.
constexpr std::uint32_t kNatUdpMaxMessage = 16384;
// RTPS bytes in one datagram: with the header, IPv4 and UDP it stays under a 1500-byte MTU.
constexpr std::size_t kNatUdpDatagramPayload = 1400;
constexpr std::size_t kNatUdpHeaderBytes = 24;
constexpr std::size_t kNatUdpFragmentHeaderBytes = 32;
constexpr std::size_t kNatUdpFragmentPayload = kNatUdpDatagramPayload - (kNatUdpFragmentHeaderBytes - kNatUdpHeaderBytes);

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

// The channel a client's initial peer names: "the server's discovery channel, whatever its
// participant id". Fast DDS's own ports depend on the id, which a client cannot know (a process
// that made and deleted participants before, such as a test binary, hands out higher ids). The
// server's transport takes it for the first channel Fast DDS opened on it, which is the
// participant's metatraffic unicast channel (RTPSParticipantImpl opens it before the user ones).
constexpr std::uint32_t kNatUdpServerDiscoveryChannel = 1;

// A direct locator for ADDRESS:PORT (the server's), with logical channel `channel`.
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

  // A message arriving in pieces; only the receive thread touches these.
  struct Partial {
    std::vector<std::uint8_t> bytes;
    std::vector<bool> have;
    std::uint16_t received = 0;
    std::size_t size = 0;  // known once the last piece came
    std::uint32_t channel = 0;
    std::chrono::steady_clock::time_point first;
  };

  Locator self_locator(std::uint32_t channel) const;
  void receive_loop();
  void deliver(const Token& token, const sockaddr_in& from, std::uint32_t channel, const std::uint8_t* data,
               std::size_t size);
  // A piece of a message; delivers the message when it is whole.
  void reassemble(const Token& token, const sockaddr_in& from, const std::uint8_t* datagram, std::size_t size);
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
  std::optional<std::uint32_t> first_channel_;    // the metatraffic unicast one

  mutable std::shared_mutex learned_mutex_;
  std::map<Token, Learned> learned_;

  std::atomic<std::uint32_t> next_message_id_{0};
  struct PartialKey {
    std::uint32_t address;  // the source, network order
    std::uint16_t port;
    Token token;
    std::uint32_t id;
    auto operator<=>(const PartialKey&) const = default;
  };
  std::map<PartialKey, Partial> partial_;
  std::chrono::steady_clock::time_point last_expiry_{};
};

}  // namespace throng::protocol::dds_detail
