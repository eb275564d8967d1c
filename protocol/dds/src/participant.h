#pragma once
// One DomainParticipant with every Throng type registered and every topic created, plus helpers
// that create endpoints from the XML profiles and throw TransportError naming what failed.
// Deleting it deletes every entity created through it (listeners must outlive it).
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <atomic>
#include <cstdint>
#include <map>
#include <set>
#include <memory>
#include <shared_mutex>
#include <string>

#include "qos.h"
#include "throng/protocol/dds_transport.h"

namespace throng::protocol::dds_detail {

struct Topics {
  eprosima::fastdds::dds::Topic* match_info = nullptr;
  eprosima::fastdds::dds::Topic* join_request = nullptr;
  eprosima::fastdds::dds::Topic* join_reply = nullptr;
  eprosima::fastdds::dds::Topic* command = nullptr;
  eprosima::fastdds::dds::Topic* snapshot = nullptr;
  eprosima::fastdds::dds::Topic* param_update = nullptr;
  eprosima::fastdds::dds::Topic* param_reply = nullptr;
  eprosima::fastdds::dds::Topic* server_stats = nullptr;
  eprosima::fastdds::dds::Topic* contacts = nullptr;
  // Server to server only (a hot standby), created by create_standby_topics(): under DDS Security
  // a client's permissions do not grant them, and creating a topic it may not use would fail.
  eprosima::fastdds::dds::Topic* tick_inputs = nullptr;
  eprosima::fastdds::dds::Topic* standby_request = nullptr;
  eprosima::fastdds::dds::Topic* standby_sync = nullptr;
  eprosima::fastdds::dds::Topic* primary = nullptr;
};

// Remembers the authenticated identity of each remote participant (DDS Security only): Fast DDS
// reports a secure participant as discovered only once its authentication succeeded, with the
// identity token whose dds.cert.sn is its certificate's subject name.
class IdentityDirectory final : public eprosima::fastdds::dds::DomainParticipantListener {
 public:
  explicit IdentityDirectory(bool secure) : secure_(secure) {}
  void on_participant_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override;
  // Participants whose authentication failed (a foreign CA, an expired or revoked certificate, a
  // permissions document that does not verify): Fast DDS only logs why at warning level.
  void onParticipantAuthentication(eprosima::fastdds::dds::DomainParticipant* participant,
                                   eprosima::fastrtps::rtps::ParticipantAuthenticationInfo&& info) override;
  std::string identity_of(const ParticipantKey& key) const;
  std::uint64_t refused() const { return refused_.load(); }

 private:
  const bool secure_;
  mutable std::shared_mutex mutex_;
  std::map<ParticipantKey, std::string> names_;
  std::set<ParticipantKey> pending_;  // discovered, not yet authorized (DDS Security only)
  std::atomic<std::uint64_t> refused_{0};
};

// The common name (CN) in a subject name as OpenSSL prints it ("CN=x,O=y" or "/O=y/CN=x"); empty
// when there is none.
std::string common_name(const std::string& subject);

class Participant {
 public:
  explicit Participant(const TransportOptions& options);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  const Topics& topics() const { return topics_; }
  // Creates the server-to-server topics (Topics::tick_inputs ...); a second call does nothing.
  void create_standby_topics();
  eprosima::fastdds::dds::DomainParticipant& dds() { return *participant_; }

  // The participant's shared publisher/subscriber (default partition).
  eprosima::fastdds::dds::Publisher& publisher() { return *publisher_; }
  eprosima::fastdds::dds::Subscriber& subscriber() { return *subscriber_; }

  // A publisher/subscriber in one named partition (per-client snapshots).
  eprosima::fastdds::dds::Publisher& create_partition_publisher(const std::string& partition);
  eprosima::fastdds::dds::Subscriber& create_partition_subscriber(const std::string& partition);

  eprosima::fastdds::dds::DataWriter& create_writer(eprosima::fastdds::dds::Publisher& publisher,
                                                    eprosima::fastdds::dds::Topic& topic, const char* profile,
                                                    eprosima::fastdds::dds::DataWriterListener* listener = nullptr);
  eprosima::fastdds::dds::DataReader& create_reader(eprosima::fastdds::dds::Subscriber& subscriber,
                                                    eprosima::fastdds::dds::Topic& topic, const char* profile,
                                                    eprosima::fastdds::dds::DataReaderListener* listener);

  // The authenticated identity (certificate common name) of the remote participant with this GUID
  // prefix, as DDS Security reported it at discovery; empty without Security or for a participant
  // not (or no longer) discovered.
  std::string identity_of(const ParticipantKey& key) const;
  // Authentication failures of remote participants so far (DDS Security only).
  std::uint64_t participants_refused() const { return identities_->refused(); }

  // Deletes a partition publisher/subscriber and the endpoints in it.
  void delete_publisher(eprosima::fastdds::dds::Publisher& publisher);
  void delete_subscriber(eprosima::fastdds::dds::Subscriber& subscriber);

 private:
  std::string where() const;

  int domain_id_ = 0;
  // Before the participant: it calls the directory until it is deleted.
  std::unique_ptr<IdentityDirectory> identities_;
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  Topics topics_;
};

}  // namespace throng::protocol::dds_detail
