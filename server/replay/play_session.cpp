// Publishing a played tick exactly as throng-server publishes a live one (see play_session.h).
#include "play_session.h"

#include <algorithm>
#include <map>
#include <set>

#include <fmt/format.h>

#include "throng/world/world.h"

namespace throng::replay {

namespace {

// A flood of requests must not grow the inbox without bound (the live server's input queue is
// bounded too); what is over the cap is dropped and counted.
constexpr std::size_t kInboxCap = 4096;

double quantile(std::vector<double>& v, double q) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

PlaySession::PlaySession(matchlog::LogPlayer& player, protocol::ServerTransport& transport, WatcherOptions watcher_options)
    : player_(player), transport_(transport), watchers_(player.header().config.interest, watcher_options) {}

void PlaySession::start() {
  transport_.start(protocol::ServerTransport::Handlers{
      [this](protocol::JoinRequest&& r) {
        std::lock_guard lock(inbox_.mutex);
        if (inbox_.joins.size() < kInboxCap) inbox_.joins.push_back(std::move(r));
        else ++inbox_.dropped;
      },
      [this](protocol::Command&& c) {
        std::lock_guard lock(inbox_.mutex);
        if (inbox_.command_clients.size() < kInboxCap) inbox_.command_clients.push_back(c.client_id);
        else ++inbox_.dropped;
      },
      [this](protocol::ParamUpdate&& u) {
        std::lock_guard lock(inbox_.mutex);
        if (inbox_.params.size() < kInboxCap) inbox_.params.push_back(std::move(u));
        else ++inbox_.dropped;
      },
      {},  // a replay feeds no hot standby
      {},  // and claims no match
  });
  transport_.publish_match_info(player_.match().match_info());
}

void PlaySession::after_seek(const matchlog::SeekResult& seek) {
  if (seek.hash_mismatches > 0) {
    if (totals_.first_mismatch_tick == 0) totals_.first_mismatch_tick = seek.first_mismatch_tick;
    totals_.hash_mismatches += seek.hash_mismatches;
  }
  // After a seek (whose join events the player consumed) the partitions come from the match.
  std::map<std::uint32_t, std::string> connected;
  for (const auto& c : player_.match().clients()) connected.emplace(c.client_id, c.partition);
  for (auto it = logged_channels_.begin(); it != logged_channels_.end();) {
    if (connected.count(it->first) == 0) {
      transport_.close_client_channel(it->first);
      it = logged_channels_.erase(it);
    } else {
      ++it;
    }
  }
  for (const auto& [id, partition] : connected) {
    if (logged_channels_.count(id) != 0) continue;
    logged_channels_[id] = partition;
    transport_.open_client_channel(id, partition);
  }
  transport_.publish_match_info(player_.match().match_info());
}

void PlaySession::publish_tick(Clock::time_point now, double work_s, std::uint64_t overruns) {
  const match::Match& m = player_.match();
  const match::Outbox& out = player_.outbox();
  const match::TickReport& report = player_.last_report();
  ++totals_.ticks_played;
  last_mismatch_ = !player_.last_hash_matched();
  if (last_mismatch_ && totals_.hash_mismatches++ == 0) totals_.first_mismatch_tick = report.tick;

  // As live: snapshots first (a client that joined this tick has no channel yet), then events.
  for (std::size_t i = 0; i < out.snapshot_count; ++i) transport_.publish_snapshot(out.snapshots[i]);
  for (const auto& e : out.client_events) {
    if (e.kind == match::ClientEvent::Kind::joined) {
      logged_channels_[e.client_id] = e.partition;
      transport_.open_client_channel(e.client_id, e.partition);
    } else {
      logged_channels_.erase(e.client_id);
      transport_.close_client_channel(e.client_id);
    }
  }
  for (const auto& r : out.join_replies) transport_.publish_join_reply(r);
  for (const auto& r : out.param_replies) transport_.publish_param_reply(r);
  if (out.match_info_changed) transport_.publish_match_info(m.match_info());

  serve_watchers(now, false);
  push_events_ += report.push_events;
  work_window_.push_back(work_s);
  if (report.tick % player_.tick_hz() == 0) publish_stats(overruns, false);
}

void PlaySession::serve_watchers(Clock::time_point now, bool ending) {
  {
    std::lock_guard lock(inbox_.mutex);
    joins_.swap(inbox_.joins);
    params_.swap(inbox_.params);
    command_clients_.swap(inbox_.command_clients);
    totals_.inputs_dropped += inbox_.dropped;
    inbox_.dropped = 0;
  }
  const match::Match& m = player_.match();
  for (std::uint32_t id : command_clients_) watchers_.note_command(id, now);
  command_clients_.clear();

  for (const auto& u : params_) {
    protocol::ParamReply r;
    r.request_id = u.request_id;
    r.ok = false;
    r.error = "this is a replay of a logged match: it takes no parameter changes";
    r.param_version = m.match_info().param_version;
    r.tick = m.tick_index();
    transport_.publish_param_reply(r);
    ++totals_.param_updates_refused;
  }
  params_.clear();

  changes_.clear();
  watchers_.handle_requests(joins_, m, ending, now, changes_);
  joins_.clear();
  watchers_.expire(now, changes_);
  apply_channels(changes_);
  for (const auto& r : changes_.replies) transport_.publish_join_reply(r);
  if (ending) return;

  watchers_.build_snapshots(m, watcher_snapshots_);
  for (const auto& s : watcher_snapshots_) transport_.publish_snapshot(s);
}

void PlaySession::apply_channels(const WatcherChanges& changes) {
  for (const auto& c : changes.channels) {
    if (c.partition.empty()) transport_.close_client_channel(c.client_id);
    else transport_.open_client_channel(c.client_id, c.partition);
  }
}

void PlaySession::publish_stats(std::uint64_t overruns, bool ended) {
  const match::Match& m = player_.match();
  protocol::ServerStats st;
  st.tick = m.tick_index();
  st.tick_hz = player_.tick_hz();
  st.clients = m.client_count();  // the logged clients, as the server counted them
  st.bodies = static_cast<std::uint32_t>(m.world().pos_x().size());
  st.tick_ms_p50 = static_cast<float>(quantile(work_window_, 0.5) * 1e3);
  st.tick_ms_p99 = static_cast<float>(quantile(work_window_, 0.99) * 1e3);
  st.tick_ms_max = work_window_.empty() ? 0.0f : static_cast<float>(*std::max_element(work_window_.begin(), work_window_.end()) * 1e3);
  st.overruns = overruns;
  st.commands_accepted = m.commands_accepted_total();
  for (auto n : m.rejected_by_reason()) st.commands_rejected += n;
  const auto c = transport_.counters();
  st.snapshot_bytes = c.snapshot_bytes;
  st.snapshot_samples = c.snapshot_samples;
  st.push_events = push_events_;
  st.state_hash = m.state_hash();
  st.state = ended ? protocol::MatchState::ended : protocol::MatchState::running;
  transport_.publish_stats(st);
  work_window_.clear();
}

void PlaySession::end(std::uint64_t overruns) {
  serve_watchers(Clock::now(), true);  // last requests are answered, joins refused
  protocol::MatchInfo info = player_.match().match_info();
  // A log whose server was killed never reached "ended": the playback ends the match anyway.
  info.state = protocol::MatchState::ended;
  transport_.publish_match_info(info);
  publish_stats(overruns, true);
  transport_.flush(std::chrono::seconds(2));  // watchers must hear "ended" before we vanish
}

}  // namespace throng::replay
