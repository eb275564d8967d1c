#include "participant.h"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "throngPubSubTypes.h"
#include "type_support.h"

namespace throng::protocol::dds_detail {

namespace dds = eprosima::fastdds::dds;

namespace {

// Registers the type and creates the topic; the type name is the IDL one ("throng::v1::...").
template <class Generated>
dds::Topic* make_topic(dds::DomainParticipant& participant, const char* topic_name, const std::string& where) {
  dds::TypeSupport type(new ThrongPubSubType<Generated>());
  if (type.register_type(&participant) != ReturnCode_t::RETCODE_OK)
    throw TransportError(where + "cannot register type " + type.get_type_name() + " for topic " + topic_name);
  dds::Topic* topic = participant.create_topic(topic_name, type.get_type_name(), dds::TOPIC_QOS_DEFAULT);
  if (topic == nullptr) throw TransportError(where + "cannot create topic " + topic_name);
  return topic;
}

void destroy(dds::DomainParticipant* participant) {
  if (participant == nullptr) return;
  delete_participant(participant);
}

}  // namespace

namespace {
ParticipantKey key_of(const eprosima::fastrtps::rtps::GuidPrefix_t& prefix) {
  ParticipantKey key;
  for (std::size_t i = 0; i < key.bytes.size(); ++i) key.bytes[i] = prefix.value[i];
  return key;
}
}  // namespace

// Fast DDS 2.9 reports a secure participant as discovered at its first announcement, before any
// handshake, and raises the authentication callback only for some failures (a certificate of a
// foreign CA is refused without one). So a participant counts as refused when authentication
// says so, or when it goes away without ever having been authorized.
void IdentityDirectory::on_participant_discovery(dds::DomainParticipant*,
                                                 eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) {
  using Status = eprosima::fastrtps::rtps::ParticipantDiscoveryInfo::DISCOVERY_STATUS;
  const ParticipantKey key = key_of(info.info.m_guid.guidPrefix);
  std::unique_lock lock(mutex_);
  if (info.status == Status::REMOVED_PARTICIPANT || info.status == Status::DROPPED_PARTICIPANT) {
    names_.erase(key);
    if (pending_.erase(key) > 0) ++refused_;
    return;
  }
  if (info.status == Status::DISCOVERED_PARTICIPANT && secure_) pending_.insert(key);
  // The identity token is the remote's claim; access control, not this name, keeps a client out
  // of partitions that are not its own (a false claim only earns a partition its holder may not
  // read: protocol/security/README.md).
  for (const auto& property : info.info.identity_token_.properties()) {
    if (property.name() != "dds.cert.sn") continue;
    const std::string cn = common_name(property.value());
    if (!cn.empty()) names_[key] = cn;
  }
}

void IdentityDirectory::onParticipantAuthentication(dds::DomainParticipant*,
                                                    eprosima::fastrtps::rtps::ParticipantAuthenticationInfo&& info) {
  const ParticipantKey key = key_of(info.guid.guidPrefix);
  std::unique_lock lock(mutex_);
  pending_.erase(key);
  if (info.status == eprosima::fastrtps::rtps::ParticipantAuthenticationInfo::UNAUTHORIZED_PARTICIPANT) {
    ++refused_;
    names_.erase(key);
  }
}

std::string IdentityDirectory::identity_of(const ParticipantKey& key) const {
  std::shared_lock lock(mutex_);
  const auto it = names_.find(key);
  return it == names_.end() ? std::string() : it->second;
}

std::string common_name(const std::string& subject) {
  for (std::size_t at = subject.find("CN="); at != std::string::npos; at = subject.find("CN=", at + 1)) {
    if (at != 0 && subject[at - 1] != ',' && subject[at - 1] != '/' && subject[at - 1] != ' ') continue;
    const std::size_t begin = at + 3;
    const std::size_t end = subject.find_first_of(",/+", begin);
    return subject.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
  }
  return {};
}

Participant::Participant(const TransportOptions& options)
    : domain_id_(options.domain_id),
      identities_(std::make_unique<IdentityDirectory>(options.security.has_value())),
      participant_(create_participant(options, identities_.get())) {
  try {
    const std::string w = where();
    topics_.match_info = make_topic<v1::MatchInfoPubSubType>(*participant_, kTopicMatchInfo, w);
    topics_.join_request = make_topic<v1::JoinRequestPubSubType>(*participant_, kTopicJoinRequest, w);
    topics_.join_reply = make_topic<v1::JoinReplyPubSubType>(*participant_, kTopicJoinReply, w);
    topics_.command = make_topic<v1::CommandPubSubType>(*participant_, kTopicCommand, w);
    topics_.snapshot = make_topic<v1::SnapshotPubSubType>(*participant_, kTopicSnapshot, w);
    topics_.param_update = make_topic<v1::ParamUpdatePubSubType>(*participant_, kTopicParamUpdate, w);
    topics_.param_reply = make_topic<v1::ParamReplyPubSubType>(*participant_, kTopicParamReply, w);
    topics_.server_stats = make_topic<v1::ServerStatsPubSubType>(*participant_, kTopicServerStats, w);
    topics_.contacts = make_topic<v1::ContactPairsPubSubType>(*participant_, kTopicContacts, w);
    publisher_ = participant_->create_publisher(dds::PUBLISHER_QOS_DEFAULT);
    subscriber_ = participant_->create_subscriber(dds::SUBSCRIBER_QOS_DEFAULT);
    if (publisher_ == nullptr || subscriber_ == nullptr)
      throw TransportError(w + "cannot create the default publisher/subscriber");
  } catch (...) {
    destroy(participant_);
    throw;
  }
}

Participant::~Participant() { destroy(participant_); }

void Participant::create_standby_topics() {
  if (topics_.tick_inputs != nullptr) return;
  const std::string w = where();
  topics_.tick_inputs = make_topic<v1::TickEntryPubSubType>(*participant_, kTopicTickInputs, w);
  topics_.standby_request = make_topic<v1::StandbyRequestPubSubType>(*participant_, kTopicStandbyRequest, w);
  topics_.standby_sync = make_topic<v1::StandbySyncPubSubType>(*participant_, kTopicStandbySync, w);
  topics_.primary = make_topic<v1::PrimaryClaimPubSubType>(*participant_, kTopicPrimary, w);
}

std::string Participant::identity_of(const ParticipantKey& key) const { return identities_->identity_of(key); }

std::string Participant::where() const { return "domain " + std::to_string(domain_id_) + ": "; }

dds::Publisher& Participant::create_partition_publisher(const std::string& partition) {
  check_partition_name(partition);
  dds::PublisherQos qos = participant_->get_default_publisher_qos();
  qos.partition().push_back(partition.c_str());
  dds::Publisher* publisher = participant_->create_publisher(qos);
  if (publisher == nullptr) throw TransportError(where() + "cannot create a publisher in partition " + partition);
  return *publisher;
}

dds::Subscriber& Participant::create_partition_subscriber(const std::string& partition) {
  check_partition_name(partition);
  dds::SubscriberQos qos = participant_->get_default_subscriber_qos();
  qos.partition().push_back(partition.c_str());
  dds::Subscriber* subscriber = participant_->create_subscriber(qos);
  if (subscriber == nullptr) throw TransportError(where() + "cannot create a subscriber in partition " + partition);
  return *subscriber;
}

dds::DataWriter& Participant::create_writer(dds::Publisher& publisher, dds::Topic& topic, const char* profile,
                                            dds::DataWriterListener* listener) {
  dds::DataWriter* writer = publisher.create_datawriter(&topic, writer_qos(publisher, profile), listener);
  if (writer == nullptr)
    throw TransportError(where() + "cannot create writer on " + topic.get_name() + " with profile " + profile);
  return *writer;
}

dds::DataReader& Participant::create_reader(dds::Subscriber& subscriber, dds::Topic& topic, const char* profile,
                                            dds::DataReaderListener* listener) {
  dds::DataReader* reader = subscriber.create_datareader(&topic, reader_qos(subscriber, profile), listener);
  if (reader == nullptr)
    throw TransportError(where() + "cannot create reader on " + topic.get_name() + " with profile " + profile);
  return *reader;
}

void Participant::delete_publisher(dds::Publisher& publisher) {
  publisher.delete_contained_entities();
  participant_->delete_publisher(&publisher);
}

void Participant::delete_subscriber(dds::Subscriber& subscriber) {
  subscriber.delete_contained_entities();
  participant_->delete_subscriber(&subscriber);
}

}  // namespace throng::protocol::dds_detail
