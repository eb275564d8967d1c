#include "throng/client_sim/fleet.h"

#include <algorithm>
#include <map>
#include <mutex>
#include <random>
#include <stdexcept>
#include <unordered_map>

#include <fmt/format.h>

#include "throng/protocol/dds_transport.h"

namespace throng::client_sim {

namespace {
// splitmix64: well-spread per-bot nonces and seeds from one fleet seed.
std::uint64_t splitmix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}
}  // namespace

struct Fleet::Impl {
  FleetOptions options;
  std::vector<std::string> default_behaviors;

  // --- written by DDS threads, guarded by inbox_mutex ---
  mutable std::mutex inbox_mutex;
  std::vector<protocol::JoinReply> inbox;
  std::shared_ptr<const MatchView> match;
  std::uint64_t match_version = 0;
  std::vector<protocol::ServerStats> stats_history;
  bool ended = false;

  // --- driving thread only ---
  std::vector<std::unique_ptr<Bot>> bots;
  std::vector<std::size_t> bot_transport;  // bot index -> transports index
  std::unordered_map<std::uint64_t, std::size_t> by_nonce;
  std::unordered_map<std::uint64_t, protocol::JoinReply> seen_replies;  // by nonce, last processed
  std::vector<protocol::JoinReply> accepted;
  std::map<std::uint32_t, std::uint32_t> client_entities;  // client id -> entity (connected)
  std::vector<std::uint32_t> other_entities;
  std::uint64_t applied_match_version = 0;
  std::uint64_t send_errors = 0;
  std::vector<protocol::Command> commands;
  std::size_t next_index = 0;
  std::uint32_t phase = 0;
  std::size_t next_to_join = 0;     // bots before this index had their first join sent
  std::size_t first_unsettled = 0;  // bots before this index are no longer joining
  std::vector<std::size_t> rejoining;  // bots whose join again waits for a reply

  // Declared last: destroyed first, so no DDS thread calls into the members above afterwards.
  std::vector<std::unique_ptr<protocol::ClientTransport>> transports;

  protocol::ClientTransport::Handlers handlers() {
    protocol::ClientTransport::Handlers h;
    h.on_match_info = [this](protocol::MatchInfo&& info) {
      auto view = std::make_shared<const MatchView>(info);
      std::lock_guard lock(inbox_mutex);
      if (view->ended()) ended = true;
      match = std::move(view);
      ++match_version;
    };
    h.on_join_reply = [this](protocol::JoinReply&& reply) {
      std::lock_guard lock(inbox_mutex);
      inbox.push_back(std::move(reply));
    };
    h.on_param_reply = [](protocol::ParamReply&&) {};
    h.on_stats = [this](protocol::ServerStats&& stats) {
      std::lock_guard lock(inbox_mutex);
      if (stats.state == protocol::MatchState::ended) ended = true;
      // Several participants deliver the same sample, in any order: keep each server tick once.
      if (!stats_history.empty() && stats.tick <= stats_history.back().tick) return;
      if (stats_history.size() >= 86400) stats_history.erase(stats_history.begin());
      stats_history.push_back(std::move(stats));
    };
    return h;
  }

  protocol::ClientTransport& make_transport(const std::string& name) {
    protocol::TransportOptions t;
    t.domain_id = options.domain_id;
    t.loopback_only = options.loopback_only;
    t.server_endpoint = options.server_endpoint;
    t.participant_name = name;
    t.security = options.security;
    auto tr = std::make_unique<protocol::ClientTransport>(t);
    tr->start(handlers());
    transports.push_back(std::move(tr));
    return *transports.back();
  }

  // Join pacing: times out and re-sends the pending joins, then sends new ones while fewer than
  // max_pending_joins wait for a reply.
  void pump_joins(TimePoint now) {
    std::size_t pending = 0;
    for (std::size_t i = first_unsettled; i < next_to_join; ++i) {
      Bot& bot = *bots[i];
      if (bot.state() != Bot::State::joining) {
        if (i == first_unsettled) ++first_unsettled;
        continue;
      }
      if (now - *bot.join_sent_at() > options.join_timeout) {
        bot.mark_timed_out();
        continue;
      }
      ++pending;
      if (now - *bot.last_join_sent_at() >= options.join_resend) send_join(i, now);
    }
    // Joins again (rejoin_after): resent and timed out as first joins are.
    std::erase_if(rejoining, [&](std::size_t i) {
      Bot& bot = *bots[i];
      if (bot.state() != Bot::State::joining) return true;
      if (now - *bot.join_sent_at() > options.join_timeout) {
        bot.mark_timed_out();
        return true;
      }
      if (now - *bot.last_join_sent_at() >= options.join_resend) send_join(i, now);
      return false;
    });
    const std::size_t limit = std::max<std::uint32_t>(1, options.max_pending_joins);
    for (; next_to_join < bots.size() && pending < limit; ++next_to_join) {
      if (bots[next_to_join]->state() != Bot::State::created) continue;  // e.g. no server for its participant
      send_join(next_to_join, now);
      ++pending;
    }
  }

  // Bots whose snapshots stopped for rejoin_after join again as new clients.
  void rejoin_silent(TimePoint now) {
    if (options.rejoin_after.count() <= 0) return;
    for (std::size_t i = 0; i < bots.size(); ++i) {
      const auto old = bots[i]->begin_rejoin(now, options.rejoin_after);
      if (!old) continue;
      transports[bot_transport[i]]->unsubscribe_snapshots(*old);
      if (client_entities.erase(*old) > 0) {
        other_entities.clear();
        for (const auto& [id, e] : client_entities) other_entities.push_back(e);
      }
      by_nonce[bots[i]->nonce()] = i;
      send_join(i, now);
      rejoining.push_back(i);
    }
  }

  void send_join(std::size_t i, TimePoint now) {
    const auto request = bots[i]->join_request(now);
    try {
      transports[bot_transport[i]]->send_join(request);
    } catch (const std::exception&) {
      ++send_errors;
    }
  }

  void process_replies() {
    std::vector<protocol::JoinReply> replies;
    {
      std::lock_guard lock(inbox_mutex);
      replies.swap(inbox);
    }
    bool entities_changed = false;
    for (auto& r : replies) {
      auto seen = seen_replies.find(r.client_nonce);
      if (seen != seen_replies.end() && seen->second.result == r.result && seen->second.client_id == r.client_id)
        continue;  // the same reply through another participant, or re-delivered
      seen_replies[r.client_nonce] = r;
      if (r.result == protocol::JoinResult::accepted) {
        accepted.push_back(r);
        client_entities[r.client_id] = r.entity;
        entities_changed = true;
      } else if (r.result == protocol::JoinResult::left) {
        entities_changed |= client_entities.erase(r.client_id) > 0;
      }
      auto it = by_nonce.find(r.client_nonce);
      if (it == by_nonce.end()) continue;
      Bot& bot = *bots[it->second];
      if (!bot.on_join_reply(r)) continue;
      Bot* target = &bot;
      transports[bot_transport[it->second]]->subscribe_snapshots(
          r.client_id, r.snapshot_partition,
          [target](protocol::Snapshot&& s, std::size_t bytes) { target->on_snapshot(s, bytes, Clock::now()); });
    }
    if (entities_changed) {
      other_entities.clear();
      for (const auto& [id, e] : client_entities) other_entities.push_back(e);
    }
  }
};

Fleet::Fleet(FleetOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->default_behaviors = expand_behavior_spec(options.behavior);
  impl_->options = std::move(options);
}

Fleet::~Fleet() {
  // Stop the DDS threads before the bots they feed go away.
  impl_->transports.clear();
}

bool Fleet::connect() {
  if (impl_->options.participant_per_client) {
    // Probe with a temporary participant so a missing server is reported before any bot starts.
    protocol::TransportOptions t;
    t.domain_id = impl_->options.domain_id;
    t.loopback_only = impl_->options.loopback_only;
    t.server_endpoint = impl_->options.server_endpoint;
    t.participant_name = impl_->options.name_prefix + "-probe";
    t.security = impl_->options.security;
    protocol::ClientTransport probe(t);
    probe.start({});
    return probe.wait_for_server(impl_->options.server_wait);
  }
  if (impl_->transports.empty()) impl_->make_transport(impl_->options.name_prefix + "-fleet");
  return impl_->transports.front()->wait_for_server(impl_->options.server_wait);
}

std::vector<std::size_t> Fleet::launch(std::size_t n) {
  std::vector<std::size_t> out;
  out.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = impl_->next_index;
    const std::string& b = impl_->default_behaviors[i % impl_->default_behaviors.size()];
    auto ids = launch(1, b);
    out.insert(out.end(), ids.begin(), ids.end());
  }
  return out;
}

std::vector<std::size_t> Fleet::launch(std::size_t n, const std::string& behavior_spec) {
  Impl& m = *impl_;
  const auto behaviors = expand_behavior_spec(behavior_spec);
  std::shared_ptr<const MatchView> match;
  {
    std::lock_guard lock(m.inbox_mutex);
    match = m.match;
  }
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = m.next_index++;
    BotConfig cfg;
    cfg.behavior = behaviors[k % behaviors.size()];
    cfg.name = fmt::format("{}-{}-{}", m.options.name_prefix, i, cfg.behavior).substr(0, 64);
    if (m.options.seed != 0) {
      cfg.nonce = splitmix(m.options.seed * 2 + 2 * i) | 1;  // never 0
      cfg.seed = splitmix(m.options.seed * 2 + 2 * i + 1) | 1;
    }
    cfg.world = m.options.world;
    const TimePoint launched = Clock::now();
    auto bot = std::make_unique<Bot>(std::move(cfg), launched);
    if (match) bot->set_match(match);

    std::size_t tr = 0;
    bool reachable = true;
    if (m.options.participant_per_client) {
      m.make_transport(bot->name());
      tr = m.transports.size() - 1;
      reachable = m.transports.back()->wait_for_server(m.options.server_wait);
    } else if (m.transports.empty()) {
      throw std::logic_error("Fleet::launch before connect()");
    }
    const std::size_t index = m.bots.size();
    m.by_nonce[bot->nonce()] = index;
    m.bot_transport.push_back(tr);
    m.bots.push_back(std::move(bot));
    if (!reachable) m.bots.back()->mark_timed_out();
    out.push_back(index);
  }
  m.pump_joins(Clock::now());
  return out;
}

void Fleet::step() {
  Impl& m = *impl_;
  m.process_replies();

  std::shared_ptr<const MatchView> match;
  {
    std::lock_guard lock(m.inbox_mutex);
    if (m.match_version != m.applied_match_version) {
      match = m.match;
      m.applied_match_version = m.match_version;
    }
  }
  m.rejoin_silent(Clock::now());
  m.pump_joins(Clock::now());
  const std::uint32_t phases = phases_per_tick();
  const std::uint32_t phase = m.phase;
  m.phase = (m.phase + 1) % phases;
  for (std::size_t i = 0; i < m.bots.size(); ++i) {
    Bot& bot = *m.bots[i];
    if (match) bot.set_match(match);
    const Bot::State s = bot.state();
    if (s != Bot::State::joined || i % phases != phase) continue;
    m.commands.clear();
    bot.tick(Clock::now(), m.other_entities, m.commands);
    for (const auto& c : m.commands) {
      try {
        m.transports[m.bot_transport[i]]->send_command(c);
      } catch (const std::exception&) {
        ++m.send_errors;
      }
    }
  }
}

void Fleet::leave_all() {
  Impl& m = *impl_;
  for (std::size_t i = 0; i < m.bots.size(); ++i) {
    if (auto r = m.bots[i]->leave_request()) {
      try {
        m.transports[m.bot_transport[i]]->send_join(*r);
        // The server's command reader would otherwise keep this client's instance until the
        // whole fleet's participant goes away.
        m.transports[m.bot_transport[i]]->release_commands(r->client_id);
      } catch (const std::exception&) {
        ++m.send_errors;
      }
    }
  }
}

std::uint32_t Fleet::phases_per_tick() const { return std::max<std::uint32_t>(1, impl_->options.phases_per_tick); }

double Fleet::step_period_s() const { return 1.0 / (static_cast<double>(tick_hz()) * phases_per_tick()); }

std::size_t Fleet::size() const { return impl_->bots.size(); }
const Bot& Fleet::bot(std::size_t i) const { return *impl_->bots.at(i); }

std::uint32_t Fleet::tick_hz() const {
  std::lock_guard lock(impl_->inbox_mutex);
  return impl_->match ? impl_->match->tick_hz() : 30;
}

std::shared_ptr<const MatchView> Fleet::match() const {
  std::lock_guard lock(impl_->inbox_mutex);
  return impl_->match;
}

bool Fleet::server_ended() const {
  std::lock_guard lock(impl_->inbox_mutex);
  return impl_->ended;
}

std::optional<protocol::ServerStats> Fleet::last_server_stats() const {
  std::lock_guard lock(impl_->inbox_mutex);
  if (impl_->stats_history.empty()) return std::nullopt;
  return impl_->stats_history.back();
}

std::vector<protocol::ServerStats> Fleet::server_stats_history() const {
  std::lock_guard lock(impl_->inbox_mutex);
  return impl_->stats_history;
}

std::vector<protocol::JoinReply> Fleet::accepted_replies() const { return impl_->accepted; }
std::uint64_t Fleet::send_errors() const { return impl_->send_errors; }

FleetProgress Fleet::progress() const {
  FleetProgress p;
  for (const auto& b : impl_->bots) {
    ++p.launched;
    switch (b->state()) {
      case Bot::State::created:
      case Bot::State::joining: ++p.joining; break;
      case Bot::State::joined:
      case Bot::State::left: ++p.joined; break;
      case Bot::State::refused:
      case Bot::State::timed_out: ++p.failed; break;
    }
    if (b->has_first_snapshot()) ++p.active;
    p.snapshots += b->snapshots_received();
    p.bytes += b->bytes_received();
    p.missed_ticks += b->missed_ticks();
    p.commands_sent += b->commands_sent();
  }
  return p;
}

Samples Fleet::take_window_latency() {
  Samples all;
  for (auto& b : impl_->bots) all.append(b->take_window_latency());
  return all;
}

std::vector<BotReport> Fleet::reports() const {
  std::vector<BotReport> out;
  out.reserve(impl_->bots.size());
  const TimePoint now = Clock::now();
  for (const auto& b : impl_->bots) out.push_back(b->report(now));
  return out;
}

}  // namespace throng::client_sim
