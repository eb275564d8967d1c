// throng-server --standby (standby_server.h): DDS in, a MatchFollower, a summary out.
#include "throng/server/standby_server.h"

#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <deque>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <unistd.h>
#include <thread>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "throng/admin/admin_server.h"
#include "throng/matchlog/format.h"
#include "throng/matchlog/log_header.h"
#include "throng/matchlog/writer.h"
#include "throng/protocol/dds_transport.h"
#include "throng/protocol/security.h"
#include "throng/server/log_setup.h"
#include "throng/server/match_server.h"
#include "throng/server/memory_trimmer.h"
#include "throng/server/standby_metrics.h"
#include "throng/world/world.h"

namespace throng::server {

namespace {

using Clock = std::chrono::steady_clock;

// Entries queued by the DDS thread and not yet taken by the follow loop, and entries that arrive
// before the primary's first answer: 30 s at 30 Hz each, newest kept. Either limit only binds when
// the loop or the answer stalls; the follower then finds a gap and asks again.
constexpr std::size_t kMaxQueuedEntries = 900;
// How often an unanswered request is repeated.
constexpr auto kRequestRetry = std::chrono::seconds(2);
// No entry for this long while following: the primary is silent (logged; takeover starts here).
constexpr auto kSilenceWarning = std::chrono::seconds(1);

std::uint64_t random_nonce() {
  std::random_device rd;
  return (static_cast<std::uint64_t>(rd()) << 32) ^ rd() ^ static_cast<std::uint64_t>(::getpid());
}

protocol::TransportOptions standby_transport_options(const ServerOptions& o) {
  protocol::TransportOptions t{o.domain, o.loopback_only, "throng-standby", std::nullopt};
  // The server's identity: only it is granted the server-to-server topics.
  if (!o.security_dir.empty()) t.security = protocol::security_files(o.security_dir, protocol::kServerIdentity);
  return t;
}

}  // namespace

struct StandbyServer::Impl {
  ServerOptions options;
  std::uint64_t nonce = random_nonce();
  std::unique_ptr<protocol::StandbyTransport> transport;
  // The transport it hosts the match with after a takeover, created now: clients and their
  // readers discover it while the standby follows, not in the ticks after the primary died.
  std::unique_ptr<protocol::ServerTransport> server_transport;
  // Arrival of the newest tick entry (steady clock, ns), written on the DDS thread: how long the
  // primary has been silent, whatever the follow loop is doing.
  std::atomic<std::int64_t> last_arrival_ns{0};

  // Filled by DDS listener threads, emptied by the follow loop.
  std::mutex queue_mutex;
  std::condition_variable queue_changed;
  std::deque<protocol::TickEntry> queued;
  std::optional<protocol::StandbySync> queued_sync;
  std::uint64_t queue_dropped = 0;  // guarded by queue_mutex

  std::atomic<bool> stop_requested{false};
  std::mutex end_mutex;
  std::string end_reason;

  // The follow loop's own.
  std::unique_ptr<matchlog::MatchFollower> follower;  // non-null once an answer restored
  matchlog::LogHeader header;                         // the primary's, from its answer
  std::uint64_t primary_epoch = 1;                    // from its answer
  // The highest epoch claimed for each match (PrimaryClaim), written on the DDS thread: another
  // standby may have taken the followed match over since the answer.
  std::mutex claims_mutex;
  std::map<std::string, std::uint64_t> claimed_epochs;
  // The standby's own match log, from the checkpoint of its first answer; closed (and reported)
  // when the chain breaks, since a log cannot skip ticks it did not apply. Handed to the new
  // primary at a takeover.
  std::unique_ptr<matchlog::MatchLogWriter> log;
  std::vector<std::uint8_t> keyframe;  // reused
  std::uint32_t logs_opened = 0;
  std::deque<protocol::TickEntry> waiting;            // entries before the first answer
  bool requested = false;
  Clock::time_point last_request{};
  Clock::time_point last_entry_at{};
  bool silent = false;
  std::uint64_t mismatches_logged = 0;
  std::uint64_t divergence_reported = 0;  // first tick of the last divergence whose objects were logged
  std::atomic<double> wall_seconds{0.0};  // read by summary() from any thread

  mutable std::mutex status_mutex;
  StandbyStatus st;  // guarded by status_mutex (written by the loop, read by status())

  // --admin-port while it follows: /healthz, /readyz (ready while it follows the primary with
  // every tick's hash), /metrics (throng_standby_*). Closed at a takeover, so that the new primary
  // serves its own on the same port. Declared after what its thread reads.
  admin::MetricsRegistry registry;
  StandbyMetrics metrics{registry};
  StandbyTotals earlier_followers;  // of the followers of matches the primary hosted before (the loop's own)
  std::atomic<bool> ready{false};
  std::atomic<std::uint16_t> admin_port{0};
  std::unique_ptr<admin::AdminServer> admin;

  // After a takeover: the match server this standby became (guarded by primary_mutex).
  std::mutex primary_mutex;
  std::unique_ptr<MatchServer> primary;
  std::atomic<bool> took_over{false};  // read by the signal thread

  // The DDS participants go first: their listener threads call into the members declared after them.
  ~Impl() {
    transport.reset();
    server_transport.reset();
    admin.reset();
  }

  explicit Impl(const ServerOptions& o)
      : options(o),
        transport(std::make_unique<protocol::StandbyTransport>(standby_transport_options(o))),
        server_transport(o.takeover_after_ticks > 0 ? std::make_unique<protocol::ServerTransport>(transport_options(o))
                                                    : nullptr) {}

  void stop_all(const char* reason);
  void request_end(const char* reason) {
    {
      std::lock_guard<std::mutex> lock(end_mutex);
      if (end_reason.empty()) end_reason = reason;
    }
    stop_requested.store(true);
    queue_changed.notify_all();
  }

  void maybe_request(Clock::time_point now);
  void apply_sync(protocol::StandbySync&& sync);
  void apply_entry(protocol::TickEntry&& entry, Clock::time_point now);
  void feed(const protocol::TickEntry& entry);
  void check_silence(Clock::time_point now);
  void publish_status();
  void open_log(const matchlog::LogHeader& answer, const protocol::StandbySync& sync);
  void log_tick(std::uint64_t tick, std::uint64_t state_hash, std::uint8_t flags, const match::TickInputs& inputs);
  void stop_log(const std::string& why);
  void report_divergence();
  bool primary_gone(Clock::time_point now) const;
  // Follows until the end or a takeover; true for a takeover.
  bool follow_loop(Clock::time_point end_at);
  int host_the_match();
};

StandbyServer::StandbyServer(const ServerOptions& options) : impl_(std::make_unique<Impl>(options)) {}
StandbyServer::~StandbyServer() = default;

void StandbyServer::request_stop() { impl_->stop_all("stopped"); }
std::uint16_t StandbyServer::admin_port() const {
  if (impl_->took_over.load()) {
    std::lock_guard<std::mutex> lock(impl_->primary_mutex);
    if (impl_->primary) return impl_->primary->admin_port();
  }
  return impl_->admin_port.load();
}

// First the flag (a takeover that starts now checks it once its server exists), then the server.
void StandbyServer::Impl::stop_all(const char* reason) {
  request_end(reason);
  std::lock_guard<std::mutex> lock(primary_mutex);
  if (primary) primary->request_stop();
}

StandbyStatus StandbyServer::status() const {
  std::lock_guard<std::mutex> lock(impl_->status_mutex);
  return impl_->st;
}

// At start, and whenever the chain broke (a divergent tick, a gap): ask the primary for the match,
// again every kRequestRetry until it answers. Only once the primary reads requests and this
// standby reads its entries (wait_for_primary), so that no entry between the checkpoint and the
// first one received is lost.
void StandbyServer::Impl::maybe_request(Clock::time_point now) {
  const bool want = !follower || follower->state() == matchlog::FollowState::needs_checkpoint;
  if (!want) {
    requested = false;
    return;
  }
  if (requested && now - last_request < kRequestRetry) return;
  if (!transport->wait_for_primary(std::chrono::milliseconds(0))) return;
  protocol::StandbyRequest r;
  r.standby_nonce = nonce;
  r.have_tick = follower ? follower->tick() : 0;
  try {
    transport->request_sync(r);
  } catch (const protocol::TransportError& e) {
    spdlog::warn("standby: cannot ask the primary for the match: {}", e.what());
  }
  if (!requested) spdlog::info("standby {:016x}: asking the primary for the match (applied up to tick {})", nonce, r.have_tick);
  requested = true;
  last_request = now;
  std::lock_guard<std::mutex> lock(status_mutex);
  ++st.requests_sent;
}

void StandbyServer::Impl::apply_sync(protocol::StandbySync&& sync) {
  try {
    const matchlog::LogHeader answer =
        matchlog::header_from_json_text(std::string(sync.header_json.begin(), sync.header_json.end()));
    const bool fresh = !follower || answer.match_id != st.match_id;
    std::unique_ptr<matchlog::MatchFollower> built;
    if (fresh) {
      if (answer.build_id != matchlog::default_build_id())
        spdlog::warn("standby: the primary runs build '{}', this standby '{}': a different build may diverge (every "
                     "tick's state hash will tell)", answer.build_id, matchlog::default_build_id());
      matchlog::FollowerOptions fo;
      fo.on_applied = [this](std::uint64_t tick, std::uint64_t hash, std::uint8_t flags, const match::TickInputs& in) {
        log_tick(tick, hash, flags, in);
      };
      built = std::make_unique<matchlog::MatchFollower>(answer, fo);
    }
    matchlog::MatchFollower& f = fresh ? *built : *follower;
    const std::uint64_t restored_before = f.stats().checkpoints;
    f.on_checkpoint(sync.checkpoint);  // throws with the follower unchanged
    const bool restored = f.stats().checkpoints > restored_before;  // else older than the match (ignored)
    if (fresh) {
      if (follower) earlier_followers.add(follower->stats());
      follower = std::move(built);
      header = answer;
      stop_log("the primary now hosts another match");
      open_log(answer, sync);
      set_log_match_id(answer.match_id);
      spdlog::info("standby: following match {} (scene '{}', {} bodies, {} Hz) from tick {} ({} kB checkpoint)",
                   answer.match_id, answer.scene.name, f.match().world().pos_x().size(), answer.config.tick_hz,
                   sync.tick, sync.checkpoint.size() / 1024);
    } else if (restored) {
      spdlog::info("standby: resynchronised from the primary's checkpoint after tick {}", sync.tick);
      report_divergence();
      // A log cannot skip the ticks the standby did not apply: the next one starts here.
      stop_log(fmt::format("the standby resynchronised from the checkpoint of tick {}", sync.tick));
      open_log(header, sync);
    }
    primary_epoch = sync.epoch;
    std::lock_guard<std::mutex> lock(status_mutex);
    st.match_id = answer.match_id;
    if (!st.synced) st.first_sync_tick = sync.tick;
    st.synced = true;
    ++st.syncs_received;
  } catch (const std::exception& e) {
    spdlog::error("standby: the primary's match after tick {} does not load here: {}", sync.tick, e.what());
    std::lock_guard<std::mutex> lock(status_mutex);
    ++st.syncs_refused;
    return;
  }
  // Entries that came before the first answer (counted then): the follower drops those the
  // checkpoint covers.
  while (!waiting.empty()) {
    const protocol::TickEntry e = std::move(waiting.front());
    waiting.pop_front();
    if (e.match_id == header.match_id) feed(e);
  }
}

void StandbyServer::Impl::apply_entry(protocol::TickEntry&& entry, Clock::time_point now) {
  if (follower && entry.match_id != header.match_id) {
    // Another primary's match on the same domain.
    std::lock_guard<std::mutex> lock(status_mutex);
    ++st.entries_foreign;
    return;
  }
  last_entry_at = now;
  {
    std::lock_guard<std::mutex> lock(status_mutex);
    ++st.entries_received;
    st.primary_tick = std::max(st.primary_tick, entry.tick);
  }
  if (options.standby_entry_hook_for_tests) options.standby_entry_hook_for_tests(entry.tick, entry.entry);
  if (!follower) {
    waiting.push_back(std::move(entry));
    if (waiting.size() > kMaxQueuedEntries) {
      waiting.pop_front();
      std::lock_guard<std::mutex> lock(status_mutex);
      ++st.entries_dropped_waiting;
    }
    return;
  }
  feed(entry);
}

void StandbyServer::Impl::feed(const protocol::TickEntry& entry) {
  try {
    follower->on_tick_entry(entry.entry);
  } catch (const matchlog::LogError& e) {
    std::lock_guard<std::mutex> lock(status_mutex);
    ++st.entries_refused;
    if (st.entries_refused <= 10) spdlog::error("standby: tick entry {} refused: {}", entry.tick, e.what());
    return;
  }
  const matchlog::FollowerStats& fs = follower->stats();
  if (fs.mismatches > mismatches_logged) {
    mismatches_logged = fs.mismatches;
    stop_log(fmt::format("tick {} diverged", fs.first_mismatch_tick));
    spdlog::error("standby: tick {} diverged from the primary (its state hash differs here): asking for the match again",
                  fs.first_mismatch_tick);
  }
  if ((follower->last_applied_flags() & matchlog::kTickShutdownBegan) != 0) request_end("primary ended");
}

void StandbyServer::Impl::check_silence(Clock::time_point now) {
  if (!follower) return;
  const bool quiet = now - last_entry_at >= kSilenceWarning;
  if (quiet && !silent)
    spdlog::warn("standby: no tick entry from the primary for {} ms (last tick {})",
                 std::chrono::duration_cast<std::chrono::milliseconds>(now - last_entry_at).count(), follower->tick());
  else if (!quiet && silent)
    spdlog::info("standby: the primary's tick entries resumed");
  silent = quiet;
}

void StandbyServer::Impl::publish_status() {
  std::lock_guard<std::mutex> lock(status_mutex);
  if (!follower) return;
  st.tick = follower->tick();
  st.state_hash = follower->match().state_hash();
  st.following = follower->state() == matchlog::FollowState::following;
  st.follower = follower->stats();
  st.primary_ended = (follower->last_applied_flags() & matchlog::kTickShutdownBegan) != 0;
  if (const matchlog::Divergence& d = follower->last_divergence(); d.first_tick != 0) {
    nlohmann::json objects = nlohmann::json::array();
    for (const auto& o : d.differences) objects.push_back({{"object", o.object_id}, {"what", o.what}});
    st.divergence = {{"first_tick", d.first_tick}, {"compared_at", d.compared_at}, {"objects", objects}, {"note", d.note}};
  }
}

// From the first answer's checkpoint on (a log cannot start at tick 1 here: the ticks before it
// never reached this standby). --log auto names it after the match and this process, so that it
// never replaces the primary's log on a shared disk.
void StandbyServer::Impl::open_log(const matchlog::LogHeader& answer, const protocol::StandbySync& sync) {
  if (options.log_file.empty()) return;
  // The first log keeps the name; one begun after a resynchronisation says from which tick.
  const std::string from = logs_opened == 0 ? std::string() : fmt::format(".from-{}", sync.tick);
  std::string path;
  if (options.log_file == "auto") {
    path = fmt::format("{}/{}.standby-{}{}.tlog", options.log_dir, answer.match_id, ::getpid(), from);
  } else {
    const std::filesystem::path p(options.log_file);
    path = (p.parent_path() / (p.stem().string() + from + p.extension().string())).string();
  }
  ++logs_opened;
  try {
    matchlog::WriterOptions wo;
    wo.keyframe_snapshot_baselines = options.log_baselines;
    wo.keyframe_interval_ticks = options.log_keyframe_ticks;
    auto writer = std::make_unique<matchlog::MatchLogWriter>(path, wo);
    matchlog::LogHeader h = answer;
    h.build_id.clear();  // this binary's: it is the one that re-simulated the ticks
    writer->begin_from(h, sync.tick, sync.checkpoint);
    log = std::move(writer);
    spdlog::info("standby: match log {} from tick {} (verify with: throng-replay verify {})", path, sync.tick + 1, path);
  } catch (const std::exception& e) {
    spdlog::error("standby: cannot start its match log {}: {}; it follows without one", path, e.what());
  }
}

void StandbyServer::Impl::log_tick(std::uint64_t tick, std::uint64_t state_hash, std::uint8_t flags,
                                   const match::TickInputs& inputs) {
  if (!log) return;
  if (tick != log->next_tick()) {
    stop_log(fmt::format("tick {} came after tick {}", tick, log->next_tick() - 1));
    return;
  }
  log->append_tick(tick, inputs, state_hash, flags);
  const std::uint32_t every = log->keyframe_interval_ticks();
  if (every > 0 && tick % every == 0) {
    follower->match().save_checkpoint(keyframe, match::SaveOptions{.snapshot_baselines = options.log_baselines});
    log->append_keyframe_swap(tick, keyframe);
  }
}

void StandbyServer::Impl::stop_log(const std::string& why) {
  if (!log) return;
  const std::string path = log->path();
  try {
    log->close();
    spdlog::warn("standby: its match log {} ends here: {} (a log cannot skip ticks; it verifies up to its end)", path, why);
  } catch (const std::exception& e) {
    spdlog::error("standby: its match log {}: {}", path, e.what());
  }
  log.reset();
}

// What verify would say: the objects whose state differed from the primary's at the checkpoint
// that ended the divergence.
void StandbyServer::Impl::report_divergence() {
  const matchlog::Divergence& d = follower->last_divergence();
  if (d.first_tick == 0 || d.first_tick == divergence_reported) return;
  divergence_reported = d.first_tick;
  if (d.differences.empty()) {
    spdlog::error("standby: the divergence from tick {}: {}", d.first_tick, d.note);
    return;
  }
  std::string objects;
  for (const auto& o : d.differences) objects += fmt::format("\n  object {}: {}", o.object_id, o.what);
  spdlog::error("standby: the divergence from tick {}: objects whose state differed at tick {} (the primary's value, then this standby's){}:{}",
                d.first_tick, d.compared_at, d.differences.size() >= 20 ? " (the 20 that differ most)" : "", objects);
}

// The primary's stream stopped for longer than the takeover limit while this standby held every
// tick up to the last one it sent: the standby can continue the match exactly.
bool StandbyServer::Impl::primary_gone(Clock::time_point now) const {
  if (options.takeover_after_ticks == 0 || !follower || follower->state() != matchlog::FollowState::following) return false;
  if ((follower->last_applied_flags() & matchlog::kTickShutdownBegan) != 0) return false;
  const std::int64_t last = last_arrival_ns.load();
  if (last == 0) return false;
  const auto limit = std::chrono::duration<double>(static_cast<double>(options.takeover_after_ticks) / header.config.tick_hz);
  return now - Clock::time_point(Clock::duration(last)) > limit;
}

bool StandbyServer::Impl::follow_loop(Clock::time_point end_at) {
  std::deque<protocol::TickEntry> batch;
  std::optional<protocol::StandbySync> sync;
  while (!stop_requested.load()) {
    const auto now = Clock::now();
    if (now >= end_at) {
      request_end("duration");
      break;
    }
    maybe_request(now);
    {
      std::unique_lock<std::mutex> lock(queue_mutex);
      queue_changed.wait_for(lock, std::chrono::milliseconds(50),
                             [&] { return stop_requested.load() || !queued.empty() || queued_sync.has_value(); });
      batch.swap(queued);
      sync.swap(queued_sync);
    }
    // Entries first: an answer compares a diverged match with the primary's checkpoint after
    // stepping it on with the held entries, and those that came in the same batch belong to them.
    for (protocol::TickEntry& e : batch) apply_entry(std::move(e), Clock::now());
    batch.clear();
    if (sync) apply_sync(std::move(*sync));
    sync.reset();
    publish_status();
    metrics.update(st, earlier_followers);  // this thread is st's only writer
    ready.store(st.synced && st.following);
    if (primary_gone(Clock::now())) return true;
    check_silence(Clock::now());
  }
  return false;
}

// The takeover: the followed match, saved with its snapshot baselines, becomes a MatchServer on
// the transport made at start; it runs until the match ends as any primary does.
int StandbyServer::Impl::host_the_match() {
  const auto t0 = Clock::now();
  const std::uint64_t silent_ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(t0 - Clock::time_point(Clock::duration(last_arrival_ns.load()))).count();
  MatchServer::Takeover t;
  t.header = header;
  follower->match().save_checkpoint(t.checkpoint, match::SaveOptions{.snapshot_baselines = true});
  {
    std::lock_guard<std::mutex> lock(claims_mutex);
    const auto it = claimed_epochs.find(header.match_id);
    t.epoch = std::max(primary_epoch, it == claimed_epochs.end() ? 0 : it->second) + 1;
  }
  t.server_id = nonce | 1u;
  t.transport = std::move(server_transport);
  t.log = std::move(log);
  spdlog::warn("standby: the primary has sent nothing for {} ms (limit {} ticks) after tick {}: taking over the match",
               silent_ms, options.takeover_after_ticks, follower->tick());
  ServerOptions o = options;
  if (o.duration_s > 0) o.duration_s = std::max(0.1, o.duration_s - wall_seconds.load());  // --duration counts from the start
  if (admin) {
    // The new primary serves its own endpoint on the same port (an ephemeral one: the one the
    // standby had, if the system still has it free).
    o.admin_port = admin->port();
    ready.store(false);
    admin.reset();
  }
  {
    std::lock_guard<std::mutex> lock(primary_mutex);
    primary = std::make_unique<MatchServer>(o, std::move(t));
    took_over = true;
    if (stop_requested.load()) primary->request_stop();  // a stop that came while it was made
  }
  {
    std::lock_guard<std::mutex> lock(status_mutex);
    st.took_over = true;
  }
  spdlog::info("standby: took over in {:.1f} ms", std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  // The standby's signal thread stays: a SIGTERM reaches the hosted match through stop_all.
  return primary->run(false);
}

int StandbyServer::run(bool handle_signals) {
  Impl& m = *impl_;
  boost::asio::io_context io;
  boost::asio::signal_set signals(io);
  std::thread signal_thread;
  // Stops and joins the signal thread on every way out, exceptions included (a joinable
  // std::thread destroyed would terminate the process).
  struct SignalThreadGuard {
    boost::asio::signal_set& signals;
    boost::asio::io_context& io;
    std::thread& thread;
    ~SignalThreadGuard() {
      if (!thread.joinable()) return;
      boost::system::error_code ignored;
      signals.cancel(ignored);
      io.stop();
      thread.join();
    }
  } guard{signals, io, signal_thread};
  if (handle_signals) {
    signals.add(SIGINT);
    signals.add(SIGTERM);
    signals.async_wait([&](const boost::system::error_code& ec, int signo) {
      if (ec) return;
      spdlog::info("{} received: {}", signo == SIGINT ? "SIGINT" : "SIGTERM",
                   m.took_over.load() ? "ending the match" : "the standby stops following");
      m.stop_all("signal");
    });
    signal_thread = std::thread([&io] { io.run(); });
  }

  m.transport->start(protocol::StandbyTransport::Handlers{
      [&m](protocol::TickEntry&& e) {
        m.last_arrival_ns.store(Clock::now().time_since_epoch().count());
        {
          std::lock_guard<std::mutex> lock(m.queue_mutex);
          m.queued.push_back(std::move(e));
          if (m.queued.size() > kMaxQueuedEntries) {
            m.queued.pop_front();
            ++m.queue_dropped;
          }
        }
        m.queue_changed.notify_one();
      },
      [&m](protocol::StandbySync&& s) {
        if (std::find(s.standby_nonces.begin(), s.standby_nonces.end(), m.nonce) == s.standby_nonces.end())
          return;  // answers other standbys' requests
        {
          std::lock_guard<std::mutex> lock(m.queue_mutex);
          m.queued_sync = std::move(s);
        }
        m.queue_changed.notify_one();
      },
      [&m](protocol::PrimaryClaim&& c) {
        std::lock_guard<std::mutex> lock(m.claims_mutex);
        if (m.claimed_epochs.size() >= 64 && !m.claimed_epochs.contains(c.match_id)) return;  // bounded
        std::uint64_t& e = m.claimed_epochs[c.match_id];
        e = std::max(e, c.epoch);
      },
  });
  spdlog::info("standby {:016x}: waiting for the primary on DDS domain {} ({}{})", m.nonce, m.options.domain,
               m.options.loopback_only ? "127.0.0.1 only" : "default network",
               m.options.security_dir.empty() ? "" : ", DDS Security with the server identity");

  if (m.options.admin_port >= 0) {
    admin::AdminServerOptions ao;
    ao.bind_address = m.options.admin_bind;
    ao.port = static_cast<std::uint16_t>(m.options.admin_port);
    try {
      m.admin = std::make_unique<admin::AdminServer>(m.registry, [&m] { return m.ready.load(); }, ao);
      m.admin_port.store(m.admin->port());
      spdlog::info("standby: admin listening on {}:{} (/healthz; /readyz ready while it follows; /metrics throng_standby_*)",
                   m.options.admin_bind, m.admin->port());
    } catch (const std::exception& e) {
      // Typically the primary's own endpoint on the same host (both default to one port): the
      // standby follows without one, and a takeover opens the new primary's on that port, which
      // the dead primary no longer holds.
      spdlog::warn("standby: {}; it follows without an admin endpoint (another port: --admin-port N, or 0 for any free one)",
                   e.what());
    }
  }
  spdlog::info("standby: {}", m.options.takeover_after_ticks > 0
                                  ? fmt::format("takes over when the primary sends nothing for {} ticks",
                                                m.options.takeover_after_ticks)
                                  : std::string("never takes over (--takeover-after-ticks 0)"));
  const auto started = Clock::now();
  const auto end_at = m.options.duration_s > 0
                          ? started + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(m.options.duration_s))
                          : Clock::time_point::max();
  // A standby follows for as long as its primary hosts: the same trimming as the primary's.
  auto trimmer = MemoryTrimmer::every_seconds(m.options.trim_memory_s);
  const bool takeover = m.follow_loop(end_at);
  log_and_stop(trimmer);  // a takeover's match server starts its own
  m.wall_seconds = std::chrono::duration<double>(Clock::now() - started).count();
  if (!takeover && m.log) {
    const std::string path = m.log->path();
    try {
      m.log->close();
      const auto ls = m.log->stats();
      spdlog::info("standby: match log {} closed: {} ticks (verify with: throng-replay verify {})", path, ls.ticks_written,
                   path);
    } catch (const std::exception& e) {
      spdlog::error("standby: match log {}: {}", path, e.what());
    }
  }
  if (takeover) {
    // The standby's own readers go first: the new primary's tick entries are for standbys of its own.
    m.transport.reset();
    const StandbyStatus st = status();
    spdlog::info("standby: applied {} ticks with the primary's hash, {} checkpoints, before the takeover",
                 st.follower.applied, st.follower.checkpoints);
    return m.host_the_match();
  }

  const nlohmann::json s = summary();
  if (!m.options.summary_json.empty()) {
    std::ofstream f(m.options.summary_json);
    f << s.dump(2) << "\n";
    if (!f) spdlog::error("cannot write the summary to {}", m.options.summary_json);
  }
  const StandbyStatus st = status();
  std::fputs(fmt::format("standby summary: match {} | {} | applied {} ticks, last {} (primary's newest {}) | "
                         "mismatches {} | checkpoints {} | gaps {} | entries refused {} | end: {}\n",
                         st.match_id.empty() ? "-" : st.match_id,
                         !st.synced ? "never received the match" : st.following ? "following" : "diverged or behind",
                         st.follower.applied, st.tick, st.primary_tick, st.follower.mismatches, st.follower.checkpoints,
                         st.follower.gaps, st.entries_refused, s.value("end_reason", ""))
                 .c_str(),
             stdout);
  std::fflush(stdout);
  const int code = !st.synced ? 4 : st.following ? 0 : 3;
  spdlog::info("standby ended after {:.1f} s; exit {}", m.wall_seconds.load(), code);
  return code;
}

nlohmann::json StandbyServer::primary_summary() const {
  std::lock_guard<std::mutex> lock(impl_->primary_mutex);
  return impl_->primary ? impl_->primary->summary() : nlohmann::json();
}

nlohmann::json StandbyServer::summary() const {
  const StandbyStatus st = status();
  std::string reason;
  {
    std::lock_guard<std::mutex> lock(impl_->end_mutex);
    reason = impl_->end_reason;
  }
  std::uint64_t queue_dropped = 0;
  {
    std::lock_guard<std::mutex> lock(impl_->queue_mutex);
    queue_dropped = impl_->queue_dropped;
  }
  return nlohmann::json{
      {"role", "standby"},
      {"match_id", st.match_id},
      {"end_reason", reason},
      {"wall_seconds", impl_->wall_seconds.load()},
      {"synced", st.synced},
      {"first_sync_tick", st.first_sync_tick},
      {"following", st.following},
      {"tick", st.tick},
      {"primary_tick", st.primary_tick},
      {"state_hash", fmt::format("{:016x}", st.state_hash)},
      {"primary_ended", st.primary_ended},
      {"took_over", st.took_over},
      {"ticks_applied", st.follower.applied},
      {"mismatches", st.follower.mismatches},
      {"first_mismatch_tick", st.follower.first_mismatch_tick},
      {"checkpoints", st.follower.checkpoints},
      {"stale_checkpoints", st.follower.stale_checkpoints},
      {"stale_entries", st.follower.stale_entries},
      {"gaps", st.follower.gaps},
      {"held_dropped", st.follower.held_dropped},
      {"entries_received", st.entries_received},
      {"entries_refused", st.entries_refused},
      {"entries_foreign", st.entries_foreign},
      {"entries_dropped", st.entries_dropped_waiting + queue_dropped},
      {"requests_sent", st.requests_sent},
      {"syncs_received", st.syncs_received},
      {"syncs_refused", st.syncs_refused},
      {"divergence", st.divergence},
  };
}

}  // namespace throng::server
