#pragma once
// Small pieces shared by both transports: a reader listener that takes every sample and hands it
// on, a writer listener that counts matched readers, and a checked write.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdio>
#include <exception>
#include <fastdds/dds/core/status/PublicationMatchedStatus.hpp>
#include <fastdds/dds/core/status/SubscriptionMatchedStatus.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TopicDescription.hpp>
#include <functional>
#include <mutex>
#include <string>
#include <utility>

#include "throng/protocol/dds_transport.h"
#include "type_support.h"

namespace throng::protocol::dds_detail {

// What a reader knows of a sample besides its content.
struct SampleMeta {
  std::size_t wire_bytes = 0;  // serialized payload size
  ParticipantKey writer;       // GUID prefix of the writer: the participant that sent it
};

inline ParticipantKey participant_key(const eprosima::fastdds::dds::SampleInfo& info) {
  ParticipantKey key;
  const auto& prefix = info.sample_identity.writer_guid().guidPrefix.value;
  static_assert(sizeof(prefix) == sizeof(key.bytes));
  for (std::size_t i = 0; i < key.bytes.size(); ++i) key.bytes[i] = prefix[i];
  return key;
}

// Takes every available sample on a DDS listener thread and passes it (with its payload size and
// writer) to `sink`. A throwing sink must not unwind into Fast DDS: the error is reported and the
// next sample is delivered.
template <class Idl>
class TakeAllListener final : public eprosima::fastdds::dds::DataReaderListener {
 public:
  using Sink = std::function<void(Idl&&, const SampleMeta&)>;
  explicit TakeAllListener(Sink sink) : sink_(std::move(sink)) {}

  // Remote writers this reader is matched with. A best-effort sample written before the reader
  // matched its writer is gone, so tests (and /metrics) need the reader's side of discovery.
  void on_subscription_matched(eprosima::fastdds::dds::DataReader*,
                               const eprosima::fastdds::dds::SubscriptionMatchedStatus& status) override {
    matched_writers_.store(status.current_count);
  }
  int matched_writers() const { return matched_writers_.load(); }

  void on_data_available(eprosima::fastdds::dds::DataReader* reader) override {
    Idl sample;
    eprosima::fastdds::dds::SampleInfo info;
    while (reader->take_next_sample(&sample, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;  // dispose/unregister notifications carry no data
      try {
        sink_(std::move(sample), SampleMeta{last_deserialized_bytes(), participant_key(info)});
      } catch (const std::exception& e) {
        std::fprintf(stderr, "throng protocol: handler for %s threw: %s\n",
                     reader->get_topicdescription()->get_name().c_str(), e.what());
      }
    }
  }

 private:
  Sink sink_;
  std::atomic<int> matched_writers_{0};
};

// Counts the readers a writer is matched with; wait_matched blocks on a condition variable.
class MatchCounter final : public eprosima::fastdds::dds::DataWriterListener {
 public:
  void on_publication_matched(eprosima::fastdds::dds::DataWriter*,
                              const eprosima::fastdds::dds::PublicationMatchedStatus& status) override {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      matched_ = status.current_count;
    }
    changed_.notify_all();
  }

  // Waits until at least one reader is matched; false if the deadline passes first.
  bool wait_until(std::chrono::steady_clock::time_point deadline) {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_until(lock, deadline, [this] { return matched_ > 0; });
  }
  int matched() {
    std::lock_guard<std::mutex> lock(mutex_);
    return matched_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  int matched_ = 0;
};

// Writes one sample and returns its serialized payload size. Throws TransportError when Fast DDS
// refuses the write.
template <class Idl>
std::size_t write_sample(eprosima::fastdds::dds::DataWriter& writer, Idl& sample) {
  if (!writer.write(&sample))
    throw TransportError("cannot write a sample on " + writer.get_topic()->get_name());
  return last_serialized_bytes();
}

}  // namespace throng::protocol::dds_detail
