#pragma once
// The primary's side of a hot standby (docs/design/standby.md): after each tick it publishes the
// tick's entry (the match log's encoding) while a standby listens, and answers a standby's request
// for the match with the log header and a checkpoint saved after that tick.
//
// Threads: on_request runs on a DDS listener thread and only queues; after_tick runs on the tick
// thread.
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "throng/match/match.h"
#include "throng/protocol/dds_transport.h"
#include "throng/scene/scene_def.h"

namespace throng::server {

struct StandbyFeedStats {
  std::uint64_t entries_published = 0;  // tick entries written (only while a standby listened)
  std::uint64_t syncs_sent = 0;         // answers to standby requests
  double last_sync_save_ms = 0.0;       // the last answer's checkpoint save, on the tick thread
  std::size_t last_sync_bytes = 0;
  std::uint64_t write_errors = 0;       // entries or answers Fast DDS refused (logged once, counted)
};

class StandbyFeed {
 public:
  // The match as the primary built it: what its log header says.
  StandbyFeed(const scene::SceneDef& scene, const match::MatchConfig& config, const std::string& match_id);

  // A standby asked for the match (any thread). Requests that arrive by the same tick share one
  // answer.
  void on_request(protocol::StandbyRequest&& request);

  // After the tick `tick` of `match` (its inputs are match.last_inputs()): publishes its entry when
  // a standby listens, then answers the requests queued so far with one checkpoint.
  void after_tick(const match::Match& match, std::uint64_t tick, std::uint64_t state_hash, std::uint8_t flags,
                  protocol::ServerTransport& transport);

  const StandbyFeedStats& stats() const { return stats_; }
  void set_epoch(std::uint64_t epoch) { sync_.epoch = epoch; }  // the hosting server's (PrimaryClaim)

 private:
  std::vector<std::uint8_t> header_json_;  // the log header the standby builds its match from
  std::mutex requests_mutex_;
  std::vector<std::uint64_t> request_nonces_;  // guarded by requests_mutex_
  std::vector<std::uint64_t> answering_;       // tick thread
  protocol::TickEntry entry_;                   // reused every tick
  protocol::StandbySync sync_;
  StandbyFeedStats stats_;
};

}  // namespace throng::server
