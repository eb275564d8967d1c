#include "throng/server/standby_feed.h"

#include <chrono>

#include <spdlog/spdlog.h>

#include "throng/matchlog/log_header.h"
#include "throng/matchlog/tick_record.h"

namespace throng::server {

StandbyFeed::StandbyFeed(const scene::SceneDef& scene, const match::MatchConfig& config, const std::string& match_id) {
  sync_.epoch = 1;
  entry_.match_id = match_id;
  matchlog::LogHeader h;
  h.match_id = match_id;
  h.scene = scene;
  h.config = config;
  const std::string text = matchlog::header_to_json_text(matchlog::stamp_header(std::move(h)));
  header_json_.assign(text.begin(), text.end());
}

void StandbyFeed::on_request(protocol::StandbyRequest&& request) {
  std::lock_guard<std::mutex> lock(requests_mutex_);
  // A standby repeats its request until answered: one answer per standby and tick is enough.
  for (std::uint64_t n : request_nonces_)
    if (n == request.standby_nonce) return;
  if (request_nonces_.size() < 64) request_nonces_.push_back(request.standby_nonce);
}

void StandbyFeed::after_tick(const match::Match& match, std::uint64_t tick, std::uint64_t state_hash,
                             std::uint8_t flags, protocol::ServerTransport& transport) {
  // Encoded only while a standby listens: a primary without one pays nothing. A refused write
  // costs the standby a gap (it asks again), never the match.
  if (transport.standby_matched()) {
    entry_.tick = tick;
    entry_.entry.clear();
    matchlog::encode_tick(tick, match.last_inputs(), state_hash, flags, entry_.entry);
    try {
      transport.publish_tick_entry(entry_);
      ++stats_.entries_published;
    } catch (const protocol::TransportError& e) {
      if (stats_.write_errors++ == 0) spdlog::error("hot standby: cannot publish tick entry {}: {}", tick, e.what());
    }
  }
  {
    std::lock_guard<std::mutex> lock(requests_mutex_);
    if (request_nonces_.empty()) return;
    answering_.swap(request_nonces_);
  }
  // With the snapshot baselines: a standby that takes over must send each client what it would
  // have had from this server. Saved here, on the tick thread, once per request (rare); the
  // sample leaves on Fast DDS's asynchronous writer.
  const auto t0 = std::chrono::steady_clock::now();
  match.save_checkpoint(sync_.checkpoint, match::SaveOptions{.snapshot_baselines = true});
  stats_.last_sync_save_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  stats_.last_sync_bytes = sync_.checkpoint.size();
  sync_.tick = tick;
  sync_.header_json = header_json_;
  sync_.standby_nonces = answering_;
  answering_.clear();
  try {
    transport.publish_standby_sync(sync_);
    ++stats_.syncs_sent;
    spdlog::info("hot standby: sent the match after tick {} to {} standby(s) ({} kB checkpoint, saved in {:.2f} ms)", tick,
                 sync_.standby_nonces.size(), sync_.checkpoint.size() / 1024, stats_.last_sync_save_ms);
  } catch (const protocol::TransportError& e) {
    ++stats_.write_errors;
    spdlog::error("hot standby: cannot send the match after tick {}: {} (the standby asks again)", tick, e.what());
  }
}

}  // namespace throng::server
