// ServerTransport: the match server's side. Shared writers for match info, join replies, param
// replies and stats; readers for joins, commands and param updates (created by start()); one
// Publisher + DataWriter per client for snapshots, in that client's partition (plus a contact-pairs
// writer there for the clients that asked for the debug channel).
#include <atomic>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <unordered_map>

#include "conversions.h"
#include "endpoints.h"
#include "participant.h"
#include "throng/protocol/dds_transport.h"

namespace throng::protocol {

namespace dds = eprosima::fastdds::dds;
using namespace dds_detail;

namespace {
struct SnapshotChannel {
  dds::Publisher* publisher = nullptr;  // in the client's partition; owns the writers
  dds::DataWriter* writer = nullptr;
  dds::DataWriter* contacts_writer = nullptr;  // created by the first publish_contacts
};
}  // namespace

struct ServerTransport::Impl {
  // Listeners are declared before the participant so they are destroyed after it: deleting the
  // participant deletes the readers that call them.
  std::unique_ptr<TakeAllListener<v1::JoinRequest>> join_listener;
  std::unique_ptr<TakeAllListener<v1::Command>> command_listener;
  std::unique_ptr<TakeAllListener<v1::ParamUpdate>> param_listener;
  std::unique_ptr<TakeAllListener<v1::StandbyRequest>> standby_request_listener;
  std::unique_ptr<TakeAllListener<v1::PrimaryClaim>> primary_listener;
  MatchCounter tick_inputs_matches;

  Participant participant;
  dds::DataReader* command_reader = nullptr;
  dds::DataWriter* match_info_writer = nullptr;
  dds::DataWriter* join_reply_writer = nullptr;
  dds::DataWriter* param_reply_writer = nullptr;
  dds::DataWriter* stats_writer = nullptr;
  // The hot standby's writers; null when this participant may not use those topics (below).
  dds::DataWriter* tick_inputs_writer = nullptr;
  dds::DataWriter* standby_sync_writer = nullptr;
  dds::DataWriter* primary_writer = nullptr;

  std::mutex start_mutex;
  bool started = false;

  // Shared lock to publish (many threads may), exclusive to open/close a channel.
  std::shared_mutex channels_mutex;
  std::unordered_map<std::uint32_t, SnapshotChannel> channels;

  std::atomic<std::uint64_t> snapshot_samples{0}, snapshot_bytes{0}, other_samples{0}, other_bytes{0};
  std::atomic<std::uint64_t> contacts_samples{0}, contacts_bytes{0};

  explicit Impl(const TransportOptions& options) : participant(options) {
    const Topics& t = participant.topics();
    dds::Publisher& pub = participant.publisher();
    match_info_writer = &participant.create_writer(pub, *t.match_info, kMatchInfoProfiles.writer);
    join_reply_writer = &participant.create_writer(pub, *t.join_reply, kJoinReplyProfiles.writer);
    param_reply_writer = &participant.create_writer(pub, *t.param_reply, kParamReplyProfiles.writer);
    stats_writer = &participant.create_writer(pub, *t.server_stats, kServerStatsProfiles.writer);
    // Over TCP no standby can reach this server (a TCP server has no peers of its own; --standby
    // is UDP only), and its primary-claim reader would match its own writer: Fast DDS 2.9.1 then
    // opens a TCP connection from the server to its own listener. That connection's two channels
    // share one locator, so the transport forgets one of them, whose receive thread outlives the
    // transport and can crash the process as it exits (seen: "pure virtual method called").
    if (options.listen_endpoint && options.listen_endpoint->scheme == NetEndpoint::Scheme::tcp) return;
    try {
      participant.create_standby_topics();
    } catch (const TransportError& e) {
      std::fprintf(stderr, "throng protocol: no hot standby can follow this server: %s\n", e.what());
    }
  }

  // The server-to-server endpoints, made by start(): a server that hosts a match. A standby's
  // transport made early for its takeover must not look like a primary to other standbys (or to
  // itself) before it hosts. Without them (a security directory made before these topics existed
  // grants the server none) the match runs, without standby or fencing.
  void create_standby_endpoints(Handlers& handlers) {
    if (participant.topics().tick_inputs == nullptr) return;
    const Topics& t = participant.topics();
    dds::Publisher& pub = participant.publisher();
    dds::Subscriber& sub = participant.subscriber();
    try {
      standby_request_listener = std::make_unique<TakeAllListener<v1::StandbyRequest>>(
          [h = std::move(handlers.on_standby_request)](v1::StandbyRequest&& r, const SampleMeta&) {
            if (h) h(from_idl(std::move(r)));
          });
      primary_listener = std::make_unique<TakeAllListener<v1::PrimaryClaim>>(
          [h = std::move(handlers.on_primary_claim)](v1::PrimaryClaim&& c, const SampleMeta&) {
            if (h) h(from_idl(std::move(c)));
          });
      tick_inputs_writer = &participant.create_writer(pub, *t.tick_inputs, kTickInputsProfiles.writer, &tick_inputs_matches);
      standby_sync_writer = &participant.create_writer(pub, *t.standby_sync, kStandbySyncProfiles.writer);
      primary_writer = &participant.create_writer(pub, *t.primary, kPrimaryProfiles.writer);
      participant.create_reader(sub, *t.standby_request, kStandbyRequestProfiles.reader, standby_request_listener.get());
      participant.create_reader(sub, *t.primary, kPrimaryProfiles.reader, primary_listener.get());
    } catch (const TransportError& e) {
      tick_inputs_writer = standby_sync_writer = primary_writer = nullptr;
      std::fprintf(stderr, "throng protocol: no hot standby can follow this server: %s\n", e.what());
    }
  }

  template <class Message>
  void publish_other(dds::DataWriter& writer, const Message& message) {
    auto sample = to_idl(message);
    other_bytes += write_sample(writer, sample);
    ++other_samples;
  }
};

ServerTransport::ServerTransport(const TransportOptions& options) : impl_(std::make_unique<Impl>(options)) {}

ServerTransport::~ServerTransport() = default;

void ServerTransport::start(Handlers handlers) {
  std::lock_guard<std::mutex> lock(impl_->start_mutex);
  if (impl_->started) throw TransportError("ServerTransport::start called twice");
  Impl& s = *impl_;
  // Handlers may be empty: the topic is then read and dropped, so writers still match.
  // The sender comes from the sample's metadata, never from its content: that is what binds a
  // client id to the participant that joined it.
  s.join_listener = std::make_unique<TakeAllListener<v1::JoinRequest>>(
      [&s, h = std::move(handlers.on_join)](v1::JoinRequest&& r, const SampleMeta& meta) {
        if (!h) return;
        JoinRequest request = from_idl(std::move(r));
        request.sender = meta.writer;
        request.identity = s.participant.identity_of(meta.writer);
        h(std::move(request));
      });
  s.command_listener = std::make_unique<TakeAllListener<v1::Command>>(
      [h = std::move(handlers.on_command)](v1::Command&& c, const SampleMeta& meta) {
        if (!h) return;
        Command command = from_idl(std::move(c));
        command.sender = meta.writer;
        h(std::move(command));
      });
  s.param_listener = std::make_unique<TakeAllListener<v1::ParamUpdate>>(
      [h = std::move(handlers.on_param_update)](v1::ParamUpdate&& u, const SampleMeta& meta) {
        if (!h) return;
        ParamUpdate update = from_idl(std::move(u));
        update.sender = meta.writer;
        h(std::move(update));
      });
  const Topics& t = s.participant.topics();
  dds::Subscriber& sub = s.participant.subscriber();
  s.participant.create_reader(sub, *t.join_request, kJoinRequestProfiles.reader, s.join_listener.get());
  s.command_reader = &s.participant.create_reader(sub, *t.command, kCommandProfiles.reader, s.command_listener.get());
  s.participant.create_reader(sub, *t.param_update, kParamProfiles.reader, s.param_listener.get());
  s.create_standby_endpoints(handlers);
  s.started = true;
}

void ServerTransport::flush(std::chrono::milliseconds timeout) {
  // Reliable writers only: best-effort snapshots have nothing to wait for.
  const eprosima::fastrtps::Duration_t max_wait(static_cast<std::int32_t>(timeout.count() / 1000),
                                                static_cast<std::uint32_t>((timeout.count() % 1000) * 1'000'000));
  // The tick entries too: a standby must see the last tick, whose flag says the match ended.
  for (dds::DataWriter* w : {impl_->match_info_writer, impl_->join_reply_writer, impl_->param_reply_writer, impl_->stats_writer,
                             impl_->tick_inputs_writer})
    if (w) (void)w->wait_for_acknowledgments(max_wait);
}

void ServerTransport::publish_match_info(const MatchInfo& info) { impl_->publish_other(*impl_->match_info_writer, info); }

void ServerTransport::publish_join_reply(const JoinReply& reply) {
  impl_->publish_other(*impl_->join_reply_writer, reply);
}

void ServerTransport::publish_param_reply(const ParamReply& reply) {
  impl_->publish_other(*impl_->param_reply_writer, reply);
}

void ServerTransport::publish_stats(const ServerStats& stats) { impl_->publish_other(*impl_->stats_writer, stats); }

bool ServerTransport::standby_matched() const {
  return impl_->tick_inputs_writer != nullptr && impl_->tick_inputs_matches.matched() > 0;
}

void ServerTransport::publish_tick_entry(const TickEntry& entry) {
  if (impl_->tick_inputs_writer != nullptr) impl_->publish_other(*impl_->tick_inputs_writer, entry);
}

void ServerTransport::publish_standby_sync(const StandbySync& sync) {
  if (impl_->standby_sync_writer != nullptr) impl_->publish_other(*impl_->standby_sync_writer, sync);
}

void ServerTransport::publish_primary_claim(const PrimaryClaim& claim) {
  if (impl_->primary_writer != nullptr) impl_->publish_other(*impl_->primary_writer, claim);
}

void ServerTransport::open_client_channel(std::uint32_t client_id, const std::string& partition) {
  std::unique_lock<std::shared_mutex> lock(impl_->channels_mutex);
  if (impl_->channels.contains(client_id)) return;
  Participant& p = impl_->participant;
  dds::Publisher& publisher = p.create_partition_publisher(partition);
  try {
    dds::DataWriter& writer = p.create_writer(publisher, *p.topics().snapshot, kSnapshotProfiles.writer);
    impl_->channels.emplace(client_id, SnapshotChannel{&publisher, &writer});
  } catch (...) {
    p.delete_publisher(publisher);
    throw;
  }
}

void ServerTransport::close_client_channel(std::uint32_t client_id) {
  std::unique_lock<std::shared_mutex> lock(impl_->channels_mutex);
  const auto it = impl_->channels.find(client_id);
  if (it == impl_->channels.end()) return;
  impl_->participant.delete_publisher(*it->second.publisher);
  impl_->channels.erase(it);
}

std::size_t ServerTransport::publish_snapshot(const Snapshot& snapshot) {
  std::shared_lock<std::shared_mutex> lock(impl_->channels_mutex);
  const auto it = impl_->channels.find(snapshot.client_id);
  if (it == impl_->channels.end()) return 0;
  v1::Snapshot sample = to_idl(snapshot);
  const std::size_t bytes = write_sample(*it->second.writer, sample);
  impl_->snapshot_bytes += bytes;
  ++impl_->snapshot_samples;
  return bytes;
}

std::size_t ServerTransport::publish_contacts(const ContactPairs& contacts) {
  Impl& s = *impl_;
  auto write = [&](dds::DataWriter& writer) {
    v1::ContactPairs sample = to_idl(contacts);
    const std::size_t bytes = write_sample(writer, sample);
    s.contacts_bytes += bytes;
    ++s.contacts_samples;
    return bytes;
  };
  {
    std::shared_lock<std::shared_mutex> lock(s.channels_mutex);
    const auto it = s.channels.find(contacts.client_id);
    if (it == s.channels.end()) return 0;
    if (it->second.contacts_writer) return write(*it->second.contacts_writer);
  }
  // First contacts sample of this client: its writer, in the snapshot channel's publisher.
  std::unique_lock<std::shared_mutex> lock(s.channels_mutex);
  const auto it = s.channels.find(contacts.client_id);
  if (it == s.channels.end()) return 0;
  SnapshotChannel& ch = it->second;
  if (!ch.contacts_writer)
    ch.contacts_writer = &s.participant.create_writer(*ch.publisher, *s.participant.topics().contacts,
                                                      kContactsProfiles.writer);
  return write(*ch.contacts_writer);
}

bool ServerTransport::holds_command_instance(std::uint32_t client_id) const {
  if (impl_->command_reader == nullptr) return false;
  v1::Command key;
  key.client_id(client_id);
  return impl_->command_reader->lookup_instance(&key) != dds::HANDLE_NIL;
}

TransportCounters ServerTransport::counters() const {
  TransportCounters c{impl_->snapshot_samples.load(), impl_->snapshot_bytes.load(), impl_->other_samples.load(),
                      impl_->other_bytes.load()};
  c.contacts_samples = impl_->contacts_samples.load();
  c.contacts_bytes = impl_->contacts_bytes.load();
  c.participants_refused = impl_->participant.participants_refused();
  if (impl_->command_listener) c.command_writers = static_cast<std::uint64_t>(impl_->command_listener->matched_writers());
  return c;
}

}  // namespace throng::protocol
