// StandbyTransport: a hot standby's side of the server-to-server topics. Reads the primary's tick
// entries and its answers (standby_sync), writes requests for the match (standby_request).
#include <chrono>
#include <memory>
#include <mutex>
#include <thread>

#include "conversions.h"
#include "endpoints.h"
#include "participant.h"
#include "throng/protocol/dds_transport.h"

namespace throng::protocol {

namespace dds = eprosima::fastdds::dds;
using namespace dds_detail;

struct StandbyTransport::Impl {
  // Before the participant, so they outlive the endpoints that call them.
  MatchCounter request_matches;
  std::unique_ptr<TakeAllListener<v1::TickEntry>> tick_listener;
  std::unique_ptr<TakeAllListener<v1::StandbySync>> sync_listener;
  std::unique_ptr<TakeAllListener<v1::PrimaryClaim>> claim_listener;

  Participant participant;
  dds::DataWriter* request_writer = nullptr;

  std::mutex start_mutex;
  bool started = false;

  explicit Impl(const TransportOptions& options) : participant(options) {
    participant.create_standby_topics();
    request_writer = &participant.create_writer(participant.publisher(), *participant.topics().standby_request,
                                                kStandbyRequestProfiles.writer, &request_matches);
  }
};

StandbyTransport::StandbyTransport(const TransportOptions& options) : impl_(std::make_unique<Impl>(options)) {}

StandbyTransport::~StandbyTransport() = default;

void StandbyTransport::start(Handlers handlers) {
  std::lock_guard<std::mutex> lock(impl_->start_mutex);
  if (impl_->started) throw TransportError("StandbyTransport::start called twice");
  Impl& s = *impl_;
  s.tick_listener = std::make_unique<TakeAllListener<v1::TickEntry>>(
      [h = std::move(handlers.on_tick_entry)](v1::TickEntry&& e, const SampleMeta&) {
        if (h) h(from_idl(std::move(e)));
      });
  s.sync_listener = std::make_unique<TakeAllListener<v1::StandbySync>>(
      [h = std::move(handlers.on_sync)](v1::StandbySync&& e, const SampleMeta&) {
        if (h) h(from_idl(std::move(e)));
      });
  s.claim_listener = std::make_unique<TakeAllListener<v1::PrimaryClaim>>(
      [h = std::move(handlers.on_primary_claim)](v1::PrimaryClaim&& c, const SampleMeta&) {
        if (h) h(from_idl(std::move(c)));
      });
  const Topics& t = s.participant.topics();
  dds::Subscriber& sub = s.participant.subscriber();
  s.participant.create_reader(sub, *t.primary, kPrimaryProfiles.reader, s.claim_listener.get());
  s.participant.create_reader(sub, *t.tick_inputs, kTickInputsProfiles.reader, s.tick_listener.get());
  s.participant.create_reader(sub, *t.standby_sync, kStandbySyncProfiles.reader, s.sync_listener.get());
  s.started = true;
}

// Both directions: a request answered before this standby reads the primary's tick entries would
// leave a gap between the checkpoint and the first entry it sees.
bool StandbyTransport::wait_for_primary(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  if (!impl_->request_matches.wait_until(deadline)) return false;
  while (primaries_matched() == 0) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

int StandbyTransport::primaries_matched() const {
  return impl_->tick_listener ? impl_->tick_listener->matched_writers() : 0;
}

void StandbyTransport::request_sync(const StandbyRequest& request) {
  v1::StandbyRequest sample = to_idl(request);
  write_sample(*impl_->request_writer, sample);
}

}  // namespace throng::protocol
