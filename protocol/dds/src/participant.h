#pragma once
// One DomainParticipant with every Throng type registered and every topic created, plus helpers
// that create endpoints from the XML profiles and throw TransportError naming what failed.
// Deleting it deletes every entity created through it (listeners must outlive it).
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
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
};

class Participant {
 public:
  explicit Participant(const TransportOptions& options);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  const Topics& topics() const { return topics_; }
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

  // Deletes a partition publisher/subscriber and the endpoints in it.
  void delete_publisher(eprosima::fastdds::dds::Publisher& publisher);
  void delete_subscriber(eprosima::fastdds::dds::Subscriber& subscriber);

 private:
  std::string where() const;

  int domain_id_ = 0;
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  Topics topics_;
};

}  // namespace throng::protocol::dds_detail
