#pragma once
// The DDS edge: the only code in Throng that talks to Fast DDS. Everything crossing it is a plain
// struct from messages.h; the fastddsgen types never leak out of protocol/dds/src.
//
// Threading: the handlers passed in are called on Fast DDS listener threads. They must be cheap
// and must not touch the simulation (the server's handlers only push into its input queue). All
// publish/send calls are thread-safe.
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "throng/protocol/messages.h"

namespace throng::protocol {

// DDS Security for one participant (Fast DDS's builtin plugins: DDS:Auth:PKI-DH,
// DDS:Access:Permissions, DDS:Crypto:AES-GCM-GMAC): the files of one identity, as throng-pki lays
// them out (security.h finds them by role). All paths, none empty.
struct SecurityFiles {
  std::string identity_ca;     // CA that signed every identity of the match
  std::string permissions_ca;  // CA that signed the governance and every permissions document
  std::string governance;       // signed governance (domain rules: who may join, what is encrypted)
  std::string certificate;     // this participant's identity certificate
  std::string private_key;     // and its key
  std::string permissions;     // this identity's signed permissions (topics and partitions)
};

// A server endpoint from "tcp://HOST:PORT" or "udp://HOST:PORT" (parse_endpoint). host is an IPv4
// address or a name that resolves to one.
//  tcp: Fast DDS's TCPv4 transport (one connection per client process).
//  udp: the NAT-crossing UDP transport (docs/hosting.md): datagrams, so a lost snapshot is
//       superseded by the next instead of holding every later one back.
struct NetEndpoint {
  std::string host;
  std::uint16_t port = 0;
  enum class Scheme : std::uint8_t { tcp, udp } scheme = Scheme::tcp;
  std::string text() const { return std::string(scheme == Scheme::udp ? "udp://" : "tcp://") + host + ":" + std::to_string(port); }
};

// Parses "tcp://HOST:PORT" or "udp://HOST:PORT" (port 1..65535). Throws TransportError naming
// what is wrong.
NetEndpoint parse_endpoint(const std::string& text);
// The same as a command-line check: "" when `text` parses, else the reason.
std::string check_endpoint(const std::string& text);

struct TransportOptions {
  int domain_id = 0;           // 0..231
  // true: the participant uses only 127.0.0.1 (UDPv4 whitelist + unicast discovery to 127.0.0.1,
  // plus shared memory) — what tests and the quick start use. false: Fast DDS's default
  // transports/discovery (a real network).
  bool loopback_only = true;
  std::string participant_name = "throng";
  std::optional<SecurityFiles> security;  // nullopt: no DDS Security
  // Reaching a server without multicast (a cloud, NAT): the server listens on TCP or UDP at
  // `listen_endpoint` (host 0.0.0.0 = every interface) and tells clients `public_address` (its
  // address as they see it; over TCP empty = the one they connected to, over UDP empty = the
  // listen host, which must then not be 0.0.0.0); a client reaches `server_endpoint`. Either one
  // replaces every other transport of the participant: discovery runs over that one path, with no
  // multicast and no well-known ports. loopback_only is then ignored.
  std::optional<NetEndpoint> listen_endpoint{};
  std::string public_address{};
  std::optional<NetEndpoint> server_endpoint{};
};

// Bytes and samples a transport wrote, for metrics (payload bytes as serialized, no RTPS headers).
struct TransportCounters {
  std::uint64_t snapshot_samples = 0;
  std::uint64_t snapshot_bytes = 0;
  std::uint64_t other_samples = 0;
  std::uint64_t other_bytes = 0;
  std::uint64_t contacts_samples = 0;  // the ContactPairs debug channel (opted-in clients only)
  std::uint64_t contacts_bytes = 0;
  // DDS Security: remote participants whose authentication failed (Fast DDS retries a refused
  // participant's handshake, so one stranger counts about once a second while it keeps trying).
  std::uint64_t participants_refused = 0;
  // Client command writers the server's command reader is matched with now (one per client
  // participant). Commands are best-effort: one written before its writer counted here is lost.
  std::uint64_t command_writers = 0;
};

class TransportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ServerTransport {
 public:
  struct Handlers {
    std::function<void(JoinRequest&&)> on_join;
    std::function<void(Command&&)> on_command;
    std::function<void(ParamUpdate&&)> on_param_update;
    std::function<void(StandbyRequest&&)> on_standby_request;  // a standby server asks for the match
    std::function<void(PrimaryClaim&&)> on_primary_claim;      // every server's claim, this one's too
  };
  // Creates the participant, topics, the shared writers/readers. Throws TransportError.
  explicit ServerTransport(const TransportOptions& options);
  ~ServerTransport();
  ServerTransport(const ServerTransport&) = delete;
  ServerTransport& operator=(const ServerTransport&) = delete;

  // Readers start delivering after this.
  void start(Handlers handlers);

  void publish_match_info(const MatchInfo& info);
  void publish_join_reply(const JoinReply& reply);
  void publish_param_reply(const ParamReply& reply);
  void publish_stats(const ServerStats& stats);

  // One snapshot writer per client, in its own DDS partition, so a client only ever receives its
  // own snapshots (interest management without reader-side filtering). Opening an already open
  // client or closing an unknown one is a no-op.
  void open_client_channel(std::uint32_t client_id, const std::string& partition);
  void close_client_channel(std::uint32_t client_id);
  // Returns the serialized payload size in bytes, 0 if the client has no open channel.
  std::size_t publish_snapshot(const Snapshot& snapshot);
  // The contact-pairs debug channel, in the same partition as the client's snapshots. Its writer
  // is created at the client's first contacts sample (clients that never opt in never see one)
  // and closed with the channel. Returns the payload size, 0 if the client has no open channel.
  std::size_t publish_contacts(const ContactPairs& contacts);

  // Hot standby (docs/design/standby.md). standby_matched(): a standby's tick-inputs reader is
  // matched now (the server encodes tick entries only then). Both writes are reliable; the sync
  // (megabytes) leaves on Fast DDS's asynchronous thread.
  bool standby_matched() const;
  void publish_tick_entry(const TickEntry& entry);
  void publish_standby_sync(const StandbySync& sync);
  void publish_primary_claim(const PrimaryClaim& claim);

  TransportCounters counters() const;
  // Whether the command reader still holds an instance for the client: until the client's writer
  // releases it (ClientTransport::release_commands). Fast DDS 2.9 forgets an instance only when it
  // takes a sample of it, so a writer that goes away without releasing (a vanished client, or a
  // participant deleted without it) leaves the instance for the rest of the match. For tests and
  // diagnostics; false before start().
  bool holds_command_instance(std::uint32_t client_id) const;

  // Waits (at most timeout) until every matched reader acknowledged what the reliable writers
  // sent — match info, join/param replies, stats. Called before exiting so the final "ended" match
  // info is not lost with the participant.
  void flush(std::chrono::milliseconds timeout);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A hot standby's participant (docs/design/standby.md): reads the primary's tick entries and its
// answers, asks it for the match. Under DDS Security it must hold the server identity: no other
// identity is granted these topics.
class StandbyTransport {
 public:
  struct Handlers {
    std::function<void(TickEntry&&)> on_tick_entry;
    std::function<void(StandbySync&&)> on_sync;  // every answer, other standbys' too
    std::function<void(PrimaryClaim&&)> on_primary_claim;  // every primary's claim
  };
  explicit StandbyTransport(const TransportOptions& options);
  ~StandbyTransport();
  StandbyTransport(const StandbyTransport&) = delete;
  StandbyTransport& operator=(const StandbyTransport&) = delete;

  void start(Handlers handlers);
  // Blocks until a primary's request reader is matched or the timeout passes; returns whether.
  bool wait_for_primary(std::chrono::milliseconds timeout);
  // Tick-inputs writers (primaries) this standby's reader is matched with now.
  int primaries_matched() const;
  void request_sync(const StandbyRequest& request);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A client side participant. One ClientTransport can carry many clients (bots multiplex on one
// participant, as Fast DDS struggles with hundreds of participants per host).
class ClientTransport {
 public:
  struct Handlers {
    std::function<void(MatchInfo&&)> on_match_info;
    std::function<void(JoinReply&&)> on_join_reply;  // every reply, other clients' too
    std::function<void(ParamReply&&)> on_param_reply;
    std::function<void(ServerStats&&)> on_stats;
  };
  explicit ClientTransport(const TransportOptions& options);
  ~ClientTransport();
  ClientTransport(const ClientTransport&) = delete;
  ClientTransport& operator=(const ClientTransport&) = delete;

  void start(Handlers handlers);

  // Blocks until the server's join-request and command readers are matched (discovery done) or
  // the timeout passes; returns whether they matched.
  bool wait_for_server(std::chrono::milliseconds timeout);

  void send_join(const JoinRequest& request);
  void send_command(const Command& command);
  // After a client left: tells the server's command reader that this transport sends no more
  // commands for the client (unregisters the client's instance), so the reader forgets the client
  // instead of keeping its instance for the rest of the match. False if this transport never sent
  // a command for the client.
  bool release_commands(std::uint32_t client_id);
  // An operator's parameter change. The first call creates the writer (with DDS Security only an
  // operator identity may: TransportError otherwise) and waits up to 10 s for the server's reader.
  void send_param_update(const ParamUpdate& update);

  // Subscribes to one client's snapshot partition; handler runs on a DDS thread. Subscribing an
  // already subscribed client replaces its handler.
  void subscribe_snapshots(std::uint32_t client_id, const std::string& partition,
                           std::function<void(Snapshot&&, std::size_t wire_bytes)> handler);
  void unsubscribe_snapshots(std::uint32_t client_id);

  // The same for the client's contact pairs (ServerTransport::publish_contacts), in the same
  // partition as its snapshots. Nothing arrives until the server grants the client contacts.
  void subscribe_contacts(std::uint32_t client_id, const std::string& partition,
                          std::function<void(ContactPairs&&, std::size_t wire_bytes)> handler);
  void unsubscribe_contacts(std::uint32_t client_id);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace throng::protocol
