#pragma once
// The registered type of each topic: the fastddsgen PubSubType plus what Throng needs from it.
//  - serialize/deserialize record the payload size on the calling thread (DataWriter::write and
//    DataReader::take run them synchronously), so the transports report the exact bytes on the
//    wire without serializing twice;
//  - getKey is serialized by a mutex: the generated one writes into a buffer shared by every
//    writer/reader of the type, and snapshot writers of different clients may write concurrently;
//  - no type information is announced: Fast DDS's is unreadable to at least one other vendor,
//    which then ignores our endpoints (protocol/README.md, "Interoperability").
#include <cstddef>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <mutex>

namespace throng::protocol::dds_detail {

// Payload bytes (including the 4-byte encapsulation header) of the last sample this thread
// serialized / deserialized.
std::size_t& last_serialized_bytes();
std::size_t& last_deserialized_bytes();

template <class GeneratedPubSubType>
class ThrongPubSubType final : public GeneratedPubSubType {
 public:
  ThrongPubSubType() {
    this->auto_fill_type_information(false);
    this->auto_fill_type_object(false);
  }

  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override {
    const bool ok = GeneratedPubSubType::serialize(data, payload);
    last_serialized_bytes() = ok ? payload->length : 0;
    return ok;
  }

  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
    const bool ok = GeneratedPubSubType::deserialize(payload, data);
    last_deserialized_bytes() = ok ? payload->length : 0;
    return ok;
  }

  bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle, bool force_md5) override {
    std::lock_guard<std::mutex> lock(key_mutex_);
    return GeneratedPubSubType::getKey(data, handle, force_md5);
  }

 private:
  std::mutex key_mutex_;
};

}  // namespace throng::protocol::dds_detail
