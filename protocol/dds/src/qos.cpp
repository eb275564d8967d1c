#include "qos.h"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/rtps/transport/TCPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>
#include <arpa/inet.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <cstring>
#include <map>
#include <mutex>

#include "embedded_profiles.h"
#include "nat_udp_transport.h"

namespace throng::protocol::dds_detail {

namespace dds = eprosima::fastdds::dds;

namespace {

// The XML profile manager keeps profiles per process, so the text is loaded once. A failed load is
// not fatal by itself: the same profiles may already be there (for instance from the same file
// named in FASTRTPS_DEFAULT_PROFILES_FILE); a profile that is really missing fails its lookup.
bool load_profiles_once() {
  static std::once_flag once;
  static bool loaded = false;
  std::call_once(once, [] {
    loaded = dds::DomainParticipantFactory::get_instance()->load_XML_profiles_string(
                 kProfilesXml.data(), kProfilesXml.size()) == ReturnCode_t::RETCODE_OK;
  });
  return loaded;
}

std::string profile_error(const char* what, const char* profile) {
  return std::string("cannot load ") + what + " QoS profile '" + profile + "' from the embedded copy of " +
         kProfilesSourcePath + (load_profiles_once() ? "" : " (the text did not load; Fast DDS logged why)");
}

// The builtin plugins, configured with participant properties (Fast DDS's documented names).
void add_security(dds::DomainParticipantQos& qos, const SecurityFiles& f, const std::string& where) {
  const std::pair<const char*, const std::string*> files[] = {
      {"identity CA", &f.identity_ca}, {"permissions CA", &f.permissions_ca}, {"governance", &f.governance},
      {"certificate", &f.certificate}, {"private key", &f.private_key},     {"permissions", &f.permissions}};
  for (const auto& [what, path] : files) {
    std::error_code ec;
    if (path->empty() || !std::filesystem::is_regular_file(*path, ec))
      throw TransportError(where + "DDS Security " + what + " file '" + *path + "' does not exist");
  }
  auto& props = qos.properties().properties();
  const auto set = [&props](const char* name, const std::string& value) { props.emplace_back(name, value); };
  const auto file = [](const std::string& path) { return "file://" + std::filesystem::absolute(path).string(); };
  set("dds.sec.auth.plugin", "builtin.PKI-DH");
  set("dds.sec.auth.builtin.PKI-DH.identity_ca", file(f.identity_ca));
  set("dds.sec.auth.builtin.PKI-DH.identity_certificate", file(f.certificate));
  set("dds.sec.auth.builtin.PKI-DH.private_key", file(f.private_key));
  set("dds.sec.access.plugin", "builtin.Access-Permissions");
  set("dds.sec.access.builtin.Access-Permissions.permissions_ca", file(f.permissions_ca));
  set("dds.sec.access.builtin.Access-Permissions.governance", file(f.governance));
  set("dds.sec.access.builtin.Access-Permissions.permissions", file(f.permissions));
  set("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
}

// Fast DDS says no more than "cannot create participant" at its default log level.
std::string security_refusal(const SecurityFiles& f) {
  const std::filesystem::path dir = std::filesystem::path(f.identity_ca).parent_path().parent_path();
  return "Fast DDS refused the DDS Security files (" + f.certificate +
         " expired or not signed by the identity CA, its key not matching it, or the governance or "
         "permissions not signed by the permissions CA or not granting this identity now); "
         "'throng-pki check " + dir.string() + " " + std::filesystem::path(f.certificate).parent_path().string() +
         "' says which";
}

// A name or dotted quad to a dotted IPv4 address (Fast DDS's locators take only the latter).
std::string resolve_ipv4(const std::string& host, const std::string& where) {
  in_addr a{};
  if (::inet_pton(AF_INET, host.c_str(), &a) == 1) return host;
  addrinfo hints{};
  hints.ai_family = AF_INET;
  addrinfo* found = nullptr;
  if (::getaddrinfo(host.c_str(), nullptr, &hints, &found) != 0 || found == nullptr)
    throw TransportError(where + "cannot resolve '" + host + "' to an IPv4 address");
  char text[INET_ADDRSTRLEN] = {};
  ::inet_ntop(AF_INET, &reinterpret_cast<sockaddr_in*>(found->ai_addr)->sin_addr, text, sizeof text);
  ::freeaddrinfo(found);
  return text;
}

// TCP only: the server listens on its port; a client connects to the server's as its one initial
// peer. Discovery and data then share that connection: no multicast, no well-known UDP ports.
void use_tcp(dds::DomainParticipantQos& qos, const TransportOptions& o, const std::string& where) {
  using eprosima::fastdds::rtps::TCPv4TransportDescriptor;
  using eprosima::fastrtps::rtps::IPLocator;
  using eprosima::fastrtps::rtps::Locator_t;
  auto tcp = std::make_shared<TCPv4TransportDescriptor>();
  // Snapshots and commands are small and latency-bound: Nagle would hold them for an ACK.
  tcp->enable_tcp_nodelay = true;
  if (o.listen_endpoint) {
    tcp->add_listener_port(o.listen_endpoint->port);
    const std::string address = resolve_ipv4(o.listen_endpoint->host, where);
    // Fast DDS 2.9 matches two participants on one host only when their whitelists agree about
    // loopback (fixed upstream after 2.9, PR 3733). Clients never whitelist, so a server bound to
    // one address serves other hosts (and namespaces) through it; 0.0.0.0 serves this host too, at
    // 127.0.0.1. A loopback-only listener could serve nobody and is refused.
    if (address.rfind("127.", 0) == 0)
      throw TransportError(where + "a TCP listener on " + address +
                           " is not supported (Fast DDS 2.9 cannot match it); listen on 0.0.0.0 or an interface's "
                           "address, or leave --listen out for a match on this host only (UDP on 127.0.0.1)");
    if (address != "0.0.0.0") tcp->interfaceWhiteList.push_back(address);
    if (!o.public_address.empty()) tcp->set_WAN_address(resolve_ipv4(o.public_address, where));
  }
  if (o.server_endpoint) {
    Locator_t peer;
    peer.kind = LOCATOR_KIND_TCPv4;
    IPLocator::setIPv4(peer, resolve_ipv4(o.server_endpoint->host, where));
    peer.port = o.server_endpoint->port;
    qos.wire_protocol().builtin.initialPeersList.push_back(peer);
  }
  qos.transport().user_transports.push_back(tcp);
  qos.transport().use_builtin_transports = false;
}

// 0 when a UDP socket can be bound to address:port (host order) now, else the errno that says why.
int udp_bind_error(std::uint32_t address, std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) return errno;
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(address);
  const int error = ::bind(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) == 0 ? 0 : errno;
  ::close(fd);
  return error;
}

// UDP across NAT (nat_udp_transport.h): the server binds its port and announces its public
// address; a client binds any port and has the server as its one initial peer, on the channel
// that reaches the server's discovery whatever its participant id.
void use_nat_udp(dds::DomainParticipantQos& qos, const TransportOptions& o, const std::string& where) {
  auto udp = std::make_shared<NatUdpTransportDescriptor>();
  const auto ipv4 = [&](const std::string& host) {
    in_addr a{};
    ::inet_pton(AF_INET, resolve_ipv4(host, where).c_str(), &a);
    return ntohl(a.s_addr);
  };
  if (o.listen_endpoint) {
    udp->bind_address = ipv4(o.listen_endpoint->host);
    udp->bind_port = o.listen_endpoint->port;
    udp->public_port = o.listen_endpoint->port;
    if (!o.public_address.empty()) {
      udp->public_address = ipv4(o.public_address);
    } else if (udp->bind_address != 0) {
      udp->public_address = udp->bind_address;
    } else {
      throw TransportError(where + "a UDP listener on 0.0.0.0 needs the address players reach it at "
                                   "(--public-address): over UDP the server announces it, players cannot learn it");
    }
    // Fast DDS refuses a transport that cannot bind without saying why: say it here.
    if (const int error = udp_bind_error(udp->bind_address, udp->bind_port); error != 0)
      throw TransportError(where + "cannot listen on " + o.listen_endpoint->text() + ": " + std::strerror(error));
  }
  if (o.server_endpoint) {
    qos.wire_protocol().builtin.initialPeersList.push_back(
        nat_udp_direct_locator(ipv4(o.server_endpoint->host), o.server_endpoint->port, kNatUdpServerDiscoveryChannel));
  }
  qos.transport().user_transports.push_back(udp);
  qos.transport().use_builtin_transports = false;
}

// Whether a UDP port on 127.0.0.1 can be bound now (nobody on this host listens on it).
bool udp_port_free(int port) { return udp_bind_error(INADDR_LOOPBACK, static_cast<std::uint16_t>(port)) == 0; }

// Participant ids, chosen here instead of by Fast DDS. Fast DDS 2.9.1 numbers a process's
// participants from a counter that never goes down, so a long-lived process (a standby that takes
// over, a test binary) would give its later participants ids beyond the range discovery tries on
// loopback (kLoopbackPeerRange), and two such participants never discover each other. Every
// participant made here gets an id that no participant of this process holds (Fast DDS refuses a
// second one, whatever its transports) and, over UDP, whose well-known unicast ports (RTPS: 7400 +
// 250 * domain + 10 or 11 + 2 * id) are free on this host. Another process may take the ports
// between this probe and Fast DDS's bind: Fast DDS then moves to other ports, as it does for a
// busy port without the probe.
//
// An id given back is not handed out again for a while: a participant's GUID prefix is the
// process's plus its id, so the next participant with it would also have the same GUID (and, its
// entities made in the same order, the same writer GUIDs). A peer that has not yet processed the
// old one's departure would take the new one's first samples for repeats of the old one's.
// Lowest id first otherwise: over TCP, clients look for a server's participant among ids 0..3.
constexpr auto kIdCooldown = std::chrono::seconds(30);  // longer than a participant's 20 s lease

struct ParticipantIds {
  std::mutex mutex;
  // By id: the participant holding it; null while it is being created or deleted, and for good
  // for an id a refused creation left behind (Fast DDS 2.9.1 keeps it: a second attempt with it
  // is refused).
  std::map<int, const dds::DomainParticipant*> held;
  std::map<int, std::chrono::steady_clock::time_point> released;  // when each id was last given back
  bool warned_out_of_range = false;
};

ParticipantIds& participant_ids() {
  static ParticipantIds ids;
  return ids;
}

// Whether both well-known unicast ports of the id are free on this host (false past port 65535).
bool ports_free(int domain_id, int id) {
  const int base = 7400 + 250 * domain_id + 2 * id;
  return base + 11 <= 65535 && udp_port_free(base + 10) && udp_port_free(base + 11);
}

// Called under ids.mutex.
int choose_participant_id(ParticipantIds& ids, int domain_id, bool udp) {
  const auto now = std::chrono::steady_clock::now();
  int cooling = -1;  // the usable id given back longest ago
  for (int id = 0; id < kLoopbackPeerRange; ++id) {
    if (ids.held.contains(id) || (udp && !ports_free(domain_id, id))) continue;
    const auto r = ids.released.find(id);
    if (r == ids.released.end() || now - r->second >= kIdCooldown) return id;
    if (cooling < 0 || r->second < ids.released[cooling]) cooling = id;
  }
  if (cooling >= 0) return cooling;
  // Every id of the range held or its ports busy: Fast DDS moves this one to other ports, and
  // over UDP only peers below the range can discover it.
  if (!ids.warned_out_of_range) {
    ids.warned_out_of_range = true;
    std::fprintf(stderr,
                 "throng protocol: every participant id 0..%d on DDS domain %d is taken on this host; "
                 "participants with higher ids may not discover each other\n",
                 kLoopbackPeerRange - 1, domain_id);
  }
  int id = kLoopbackPeerRange;
  while (ids.held.contains(id)) ++id;
  return id;
}

}  // namespace

dds::DomainParticipant* create_participant(const TransportOptions& options, dds::DomainParticipantListener* listener) {
  const std::string where = "cannot create participant '" + options.participant_name + "' on domain " +
                            std::to_string(options.domain_id) + ": ";
  if (options.domain_id < 0 || options.domain_id > kMaxDomainId)
    throw TransportError(where + "domain id must be 0.." + std::to_string(kMaxDomainId));
  load_profiles_once();  // before any profile lookup, including the writers' and readers'

  auto* factory = dds::DomainParticipantFactory::get_instance();
  dds::DomainParticipantQos qos = factory->get_default_participant_qos();
  const bool tcp = options.listen_endpoint.has_value() || options.server_endpoint.has_value();
  const bool nat_udp = (options.listen_endpoint && options.listen_endpoint->scheme == NetEndpoint::Scheme::udp) ||
                       (options.server_endpoint && options.server_endpoint->scheme == NetEndpoint::Scheme::udp);
  if (options.loopback_only && !tcp &&
      factory->get_participant_qos_from_profile(kLoopbackParticipantProfile, qos) != ReturnCode_t::RETCODE_OK)
    throw TransportError(where + profile_error("participant", kLoopbackParticipantProfile));
  if (nat_udp) {
    use_nat_udp(qos, options, where);
  } else if (tcp) {
    use_tcp(qos, options, where);
  }
  qos.name(options.participant_name);
  if (options.security) add_security(qos, *options.security, where);

  // The id is reserved under the lock and the participant made without it: Fast DDS's own threads
  // never wait for another participant's creation.
  ParticipantIds& ids = participant_ids();
  int id = 0;
  {
    std::lock_guard<std::mutex> lock(ids.mutex);
    id = choose_participant_id(ids, options.domain_id, !tcp);
    ids.held[id] = nullptr;
  }
  qos.wire_protocol().participant_id = id;
  dds::DomainParticipant* participant = factory->create_participant(
      static_cast<dds::DomainId_t>(options.domain_id), qos, listener,
      // Not data_on_readers: a participant listener with it would take every sample away from the
      // readers' own listeners. (Discovery and authentication callbacks are not masked.)
      dds::StatusMask::all() >> dds::StatusMask::data_on_readers());
  if (participant == nullptr)  // the id stays reserved for good (see ParticipantIds::held)
    throw TransportError(where + (options.security ? security_refusal(*options.security)
                                                   : "Fast DDS refused (ports in use or transports misconfigured; see its log)"));
  std::lock_guard<std::mutex> lock(ids.mutex);
  ids.held[id] = participant;
  return participant;
}

void delete_participant(dds::DomainParticipant* participant) {
  ParticipantIds& ids = participant_ids();
  int id = -1;
  {
    std::lock_guard<std::mutex> lock(ids.mutex);
    for (auto& [held_id, held] : ids.held)
      if (held == participant) {
        id = held_id;
        held = nullptr;  // reserved until Fast DDS has let it go
        break;
      }
  }
  const bool deleted = participant->delete_contained_entities() == ReturnCode_t::RETCODE_OK &&
                       dds::DomainParticipantFactory::get_instance()->delete_participant(participant) ==
                           ReturnCode_t::RETCODE_OK;
  if (id < 0 || !deleted) return;  // a participant Fast DDS kept keeps its id
  std::lock_guard<std::mutex> lock(ids.mutex);
  ids.held.erase(id);
  ids.released[id] = std::chrono::steady_clock::now();
}

dds::DataWriterQos writer_qos(dds::Publisher& publisher, const char* profile) {
  dds::DataWriterQos qos;
  if (publisher.get_datawriter_qos_from_profile(profile, qos) != ReturnCode_t::RETCODE_OK)
    throw TransportError(profile_error("writer", profile));
  return qos;
}

dds::DataReaderQos reader_qos(dds::Subscriber& subscriber, const char* profile) {
  dds::DataReaderQos qos;
  if (subscriber.get_datareader_qos_from_profile(profile, qos) != ReturnCode_t::RETCODE_OK)
    throw TransportError(profile_error("reader", profile));
  return qos;
}

void check_partition_name(const std::string& partition) {
  if (partition.empty()) throw TransportError("snapshot partition name is empty");
  if (partition.find_first_of("*?[]\\") != std::string::npos)
    throw TransportError("snapshot partition name '" + partition +
                         "' contains a wildcard character (* ? [ ] \\)");
}

}  // namespace throng::protocol::dds_detail
