// ClientTransport: one participant carrying any number of clients (bots multiplex on it). Shared
// writers for joins, commands (keyed by client_id) and param updates; readers for match info,
// join replies, param replies and stats (created by start()); one Subscriber + DataReader per
// subscribed client partition for snapshots, and another for contact pairs when asked for.
#include <memory>
#include <mutex>
#include <unordered_map>

#include "conversions.h"
#include "endpoints.h"
#include "participant.h"
#include "throng/protocol/dds_transport.h"

namespace throng::protocol {

namespace dds = eprosima::fastdds::dds;
using namespace dds_detail;

namespace {

constexpr std::chrono::milliseconds kParamMatchWait{10000};

// One client's subscription to a per-client topic (snapshots, contact pairs). The handler can be
// replaced while samples arrive, so the listener reads it under a mutex and calls a copy outside
// the lock.
template <class Idl, class Message>
struct PartitionSubscription {
  using Handler = std::function<void(Message&&, std::size_t wire_bytes)>;
  std::mutex handler_mutex;
  Handler handler;
  std::string partition;
  TakeAllListener<Idl> listener{[this](Idl&& s, const SampleMeta& meta) {
    Handler h;
    {
      std::lock_guard<std::mutex> lock(handler_mutex);
      h = handler;
    }
    if (h) h(from_idl(std::move(s)), meta.wire_bytes);
  }};
  dds::Subscriber* subscriber = nullptr;  // in the client's partition; owns the reader
};

using SnapshotSubscription = PartitionSubscription<v1::Snapshot, Snapshot>;
using ContactsSubscription = PartitionSubscription<v1::ContactPairs, ContactPairs>;

template <class Subscription>
using SubscriptionMap = std::unordered_map<std::uint32_t, std::unique_ptr<Subscription>>;

// Subscribes (or re-points) one client's subscription of one topic; see subscribe_snapshots.
template <class Subscription>
void subscribe(Participant& p, SubscriptionMap<Subscription>& map, std::uint32_t client_id, const std::string& partition,
               typename Subscription::Handler handler, dds::Topic& topic, const char* reader_profile) {
  check_partition_name(partition);
  if (const auto it = map.find(client_id); it != map.end()) {
    Subscription& existing = *it->second;
    {
      std::lock_guard<std::mutex> handler_lock(existing.handler_mutex);
      existing.handler = std::move(handler);
    }
    if (existing.partition != partition) {
      // Partition is a changeable QoS: the reader rematches to the new client's writer.
      dds::SubscriberQos qos = existing.subscriber->get_qos();
      qos.partition().clear();
      qos.partition().push_back(partition.c_str());
      if (existing.subscriber->set_qos(qos) != ReturnCode_t::RETCODE_OK)
        throw TransportError("cannot move client " + std::to_string(client_id) + "'s " + topic.get_name() +
                             " subscription to partition " + partition);
      existing.partition = partition;
    }
    return;
  }
  auto subscription = std::make_unique<Subscription>();
  subscription->handler = std::move(handler);
  subscription->partition = partition;
  subscription->subscriber = &p.create_partition_subscriber(partition);
  try {
    p.create_reader(*subscription->subscriber, topic, reader_profile, &subscription->listener);
  } catch (...) {
    p.delete_subscriber(*subscription->subscriber);
    throw;
  }
  map.emplace(client_id, std::move(subscription));
}

template <class Subscription>
void unsubscribe(Participant& p, SubscriptionMap<Subscription>& map, std::uint32_t client_id) {
  const auto it = map.find(client_id);
  if (it == map.end()) return;
  p.delete_subscriber(*it->second->subscriber);
  map.erase(it);
}

}  // namespace

struct ClientTransport::Impl {
  // Listeners and subscriptions are declared before the participant so they outlive it: deleting
  // the participant deletes (and waits for) the endpoints that call them.
  MatchCounter join_request_matches;
  MatchCounter command_matches;
  MatchCounter param_update_matches;
  std::unique_ptr<TakeAllListener<v1::MatchInfo>> match_info_listener;
  std::unique_ptr<TakeAllListener<v1::JoinReply>> join_reply_listener;
  std::unique_ptr<TakeAllListener<v1::ParamReply>> param_reply_listener;
  std::unique_ptr<TakeAllListener<v1::ServerStats>> stats_listener;
  std::mutex subscriptions_mutex;
  SubscriptionMap<SnapshotSubscription> subscriptions;
  SubscriptionMap<ContactsSubscription> contacts_subscriptions;

  Participant participant;
  dds::DataWriter* join_request_writer = nullptr;
  dds::DataWriter* command_writer = nullptr;
  // Created by the first send_param_update: with DDS Security only operators may write the topic,
  // and a player's participant could not even be created with the writer in it.
  std::mutex param_mutex;
  dds::DataWriter* param_update_writer = nullptr;

  std::mutex start_mutex;
  bool started = false;

  explicit Impl(const TransportOptions& options) : participant(options) {
    const Topics& t = participant.topics();
    dds::Publisher& pub = participant.publisher();
    join_request_writer =
        &participant.create_writer(pub, *t.join_request, kJoinRequestProfiles.writer, &join_request_matches);
    command_writer = &participant.create_writer(pub, *t.command, kCommandProfiles.writer, &command_matches);
  }

  template <class Idl, class Message>
  static std::unique_ptr<TakeAllListener<Idl>> forward_to(std::function<void(Message&&)> handler) {
    return std::make_unique<TakeAllListener<Idl>>([h = std::move(handler)](Idl&& sample, const SampleMeta&) {
      if (h) h(from_idl(std::move(sample)));
    });
  }
};

ClientTransport::ClientTransport(const TransportOptions& options) : impl_(std::make_unique<Impl>(options)) {}

ClientTransport::~ClientTransport() = default;

void ClientTransport::start(Handlers handlers) {
  std::lock_guard<std::mutex> lock(impl_->start_mutex);
  if (impl_->started) throw TransportError("ClientTransport::start called twice");
  Impl& c = *impl_;
  c.match_info_listener = Impl::forward_to<v1::MatchInfo>(std::move(handlers.on_match_info));
  c.join_reply_listener = Impl::forward_to<v1::JoinReply>(std::move(handlers.on_join_reply));
  c.param_reply_listener = Impl::forward_to<v1::ParamReply>(std::move(handlers.on_param_reply));
  c.stats_listener = Impl::forward_to<v1::ServerStats>(std::move(handlers.on_stats));
  const Topics& t = c.participant.topics();
  dds::Subscriber& sub = c.participant.subscriber();
  c.participant.create_reader(sub, *t.match_info, kMatchInfoProfiles.reader, c.match_info_listener.get());
  c.participant.create_reader(sub, *t.join_reply, kJoinReplyProfiles.reader, c.join_reply_listener.get());
  c.participant.create_reader(sub, *t.param_reply, kParamReplyProfiles.reader, c.param_reply_listener.get());
  c.participant.create_reader(sub, *t.server_stats, kServerStatsProfiles.reader, c.stats_listener.get());
  c.started = true;
}

bool ClientTransport::wait_for_server(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  return impl_->join_request_matches.wait_until(deadline) && impl_->command_matches.wait_until(deadline);
}

void ClientTransport::send_join(const JoinRequest& request) {
  v1::JoinRequest sample = to_idl(request);
  write_sample(*impl_->join_request_writer, sample);
}

void ClientTransport::send_command(const Command& command) {
  v1::Command sample = to_idl(command);
  write_sample(*impl_->command_writer, sample);
}

bool ClientTransport::release_commands(std::uint32_t client_id) {
  v1::Command key;
  key.client_id(client_id);
  // The handle is looked up from the key; an instance never written is not registered.
  return impl_->command_writer->unregister_instance(&key, eprosima::fastrtps::rtps::InstanceHandle_t()) ==
         ReturnCode_t::RETCODE_OK;
}

// The writer appears with the first update, which then waits for the server's reader: the topic is
// reliable but volatile, so an update written before its writer matched is never delivered.
void ClientTransport::send_param_update(const ParamUpdate& update) {
  Impl& c = *impl_;
  std::lock_guard<std::mutex> lock(c.param_mutex);
  if (c.param_update_writer == nullptr) {
    try {
      c.param_update_writer = &c.participant.create_writer(c.participant.publisher(), *c.participant.topics().param_update,
                                                           kParamProfiles.writer, &c.param_update_matches);
    } catch (const TransportError& e) {
      throw TransportError(std::string(e.what()) + " (with DDS Security only an operator identity may change parameters)");
    }
  }
  if (!c.param_update_matches.wait_until(std::chrono::steady_clock::now() + kParamMatchWait))
    throw TransportError("no server reads parameter changes on this domain (waited " +
                         std::to_string(kParamMatchWait.count()) + " ms)");
  v1::ParamUpdate sample = to_idl(update);
  write_sample(*c.param_update_writer, sample);
}

void ClientTransport::subscribe_snapshots(std::uint32_t client_id, const std::string& partition,
                                          std::function<void(Snapshot&&, std::size_t wire_bytes)> handler) {
  std::lock_guard<std::mutex> lock(impl_->subscriptions_mutex);
  Participant& p = impl_->participant;
  subscribe(p, impl_->subscriptions, client_id, partition, std::move(handler), *p.topics().snapshot,
            kSnapshotProfiles.reader);
}

void ClientTransport::unsubscribe_snapshots(std::uint32_t client_id) {
  std::lock_guard<std::mutex> lock(impl_->subscriptions_mutex);
  unsubscribe(impl_->participant, impl_->subscriptions, client_id);
}

void ClientTransport::subscribe_contacts(std::uint32_t client_id, const std::string& partition,
                                         std::function<void(ContactPairs&&, std::size_t wire_bytes)> handler) {
  std::lock_guard<std::mutex> lock(impl_->subscriptions_mutex);
  Participant& p = impl_->participant;
  subscribe(p, impl_->contacts_subscriptions, client_id, partition, std::move(handler), *p.topics().contacts,
            kContactsProfiles.reader);
}

void ClientTransport::unsubscribe_contacts(std::uint32_t client_id) {
  std::lock_guard<std::mutex> lock(impl_->subscriptions_mutex);
  unsubscribe(impl_->participant, impl_->contacts_subscriptions, client_id);
}

}  // namespace throng::protocol
