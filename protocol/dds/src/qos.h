#pragma once
// QoS for participants and endpoints, taken from the profiles in qos/throng_profiles.xml (embedded
// into the library, loaded once per process). Per-client partitions are added in code on top.
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <string>

#include "throng/protocol/dds_transport.h"

namespace throng::protocol::dds_detail {

using ReturnCode_t = eprosima::fastrtps::types::ReturnCode_t;

// Writer and reader profile of one topic (names as in throng_profiles.xml).
struct TopicProfiles {
  const char* writer;
  const char* reader;
};
inline constexpr TopicProfiles kMatchInfoProfiles{"throng_match_info_writer", "throng_match_info_reader"};
inline constexpr TopicProfiles kJoinRequestProfiles{"throng_join_request_writer", "throng_join_request_reader"};
inline constexpr TopicProfiles kJoinReplyProfiles{"throng_join_reply_writer", "throng_join_reply_reader"};
inline constexpr TopicProfiles kCommandProfiles{"throng_command_writer", "throng_command_reader"};
inline constexpr TopicProfiles kSnapshotProfiles{"throng_snapshot_writer", "throng_snapshot_reader"};
inline constexpr TopicProfiles kParamProfiles{"throng_param_writer", "throng_param_reader"};  // param_update
inline constexpr TopicProfiles kParamReplyProfiles{"throng_param_reply_writer", "throng_param_reply_reader"};
inline constexpr TopicProfiles kServerStatsProfiles{"throng_server_stats_writer", "throng_server_stats_reader"};
inline constexpr TopicProfiles kContactsProfiles{"throng_contacts_writer", "throng_contacts_reader"};
inline constexpr TopicProfiles kTickInputsProfiles{"throng_tick_inputs_writer", "throng_tick_inputs_reader"};
inline constexpr TopicProfiles kStandbyRequestProfiles{"throng_standby_request_writer", "throng_standby_request_reader"};
inline constexpr TopicProfiles kStandbySyncProfiles{"throng_standby_sync_writer", "throng_standby_sync_reader"};
inline constexpr TopicProfiles kPrimaryProfiles{"throng_primary_writer", "throng_primary_reader"};
inline constexpr const char* kLoopbackParticipantProfile = "throng_loopback_participant";
// maxInitialPeersRange of the throng_udp_loopback transport (throng_profiles.xml): the participant
// ids whose well-known ports discovery tries.
inline constexpr int kLoopbackPeerRange = 120;

// With Fast DDS's default ports, the highest domain whose 120 participant ids (kLoopbackPeerRange)
// all map to ports below 65536: on 232 Fast DDS ends the process computing the initial peers.
inline constexpr int kMaxDomainId = 231;

// Creates (and enables) a participant for the options. Throws TransportError naming the domain and
// the reason: domain id out of range, profiles not loadable, participant creation failed.
// With options.security, the participant runs Fast DDS's builtin security plugins on those files
// (each checked to exist first, so a typo is named instead of a plugin failure). `listener` (may be
// null) hears participant discovery.
eprosima::fastdds::dds::DomainParticipant* create_participant(const TransportOptions& options,
                                                              eprosima::fastdds::dds::DomainParticipantListener* listener);
// Deletes a participant made by create_participant, and everything in it; its id is free again.
void delete_participant(eprosima::fastdds::dds::DomainParticipant* participant);

eprosima::fastdds::dds::DataWriterQos writer_qos(eprosima::fastdds::dds::Publisher& publisher,
                                                 const char* profile);
eprosima::fastdds::dds::DataReaderQos reader_qos(eprosima::fastdds::dds::Subscriber& subscriber,
                                                 const char* profile);

// A partition name for one client's snapshots. Throws TransportError when empty or when it holds
// a wildcard character (* ? [ ] \), which DDS would match against other clients' partitions.
void check_partition_name(const std::string& partition);

}  // namespace throng::protocol::dds_detail
