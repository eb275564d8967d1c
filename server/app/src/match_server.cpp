#include "throng/server/match_server.h"

#include <bit>
#include <chrono>
#include <csignal>
#include <fstream>
#include <mutex>
#include <optional>
#include <random>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <spdlog/spdlog.h>

#include "throng/server/held_for.h"
#include "throng/admin/admin_server.h"
#include "throng/admin/metrics.h"
#include "throng/match/match.h"
#include "throng/matchlog/writer.h"
#include "throng/protocol/dds_transport.h"
#include "throng/protocol/security.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"
#include "throng/server/agones_sdk.h"
#include "throng/server/client_ledger.h"
#include "throng/server/duration_stats.h"
#include "throng/server/keyframe_saver.h"
#include "throng/server/log_setup.h"
#include "throng/server/memory_trimmer.h"
#include "throng/server/server_metrics.h"
#include "throng/server/server_summary.h"
#include "throng/server/standby_feed.h"
#include "throng/server/tick_schedule.h"
#include "throng/world/world.h"

namespace throng::server {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

scene::SceneDef load_scaled_scene(const ServerOptions& o) {
  scene::SceneDef s = scene::load_scene(o.scene);
  if (o.npcs > 0 && o.npcs != s.agent_count()) s = scene::scale_scene(s, o.npcs);
  return s;
}

}  // namespace

protocol::TransportOptions transport_options(const ServerOptions& o) {
  protocol::TransportOptions t{o.domain, o.loopback_only, "throng-server", std::nullopt};
  if (!o.security_dir.empty()) t.security = protocol::security_files(o.security_dir, protocol::kServerIdentity);
  if (o.listen == kListenAgones) {
    // Agones (portPolicy Passthrough): the port it allocated to the GameServer's "dds" port is
    // both the container's and the node's, and status.address is where players connect.
    if (o.agones_port == 0) throw std::runtime_error("--listen agones: AGONES_SDK_HTTP_PORT is not set (not under Agones?)");
    const AgonesEndpoint e = agones_endpoint(o.agones_port, "dds", std::chrono::seconds(30));
    t.listen_endpoint = protocol::NetEndpoint{"0.0.0.0", e.port};
    t.public_address = o.public_address.empty() ? e.address : o.public_address;
    spdlog::info("Agones allocated port {} to 'dds': listening on tcp://0.0.0.0:{}, players connect to tcp://{}:{}", e.port,
                 e.port, t.public_address, e.port);
  } else if (!o.listen.empty()) {
    t.listen_endpoint = protocol::parse_endpoint(o.listen);
    t.public_address = o.public_address;
  }
  return t;
}

namespace {

std::uint64_t random_server_id() {
  std::random_device rd;
  return ((static_cast<std::uint64_t>(rd()) << 32) ^ rd()) | 1u;  // never 0 (0: not drawn yet)
}

// The match id; from here on every log line carries it.
std::string make_match_id(const std::string& scene_name) {
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  std::string id = scene_name + "-" + std::to_string(std::chrono::duration_cast<std::chrono::seconds>(now).count()) +
                   "-" + std::to_string(::getpid());
  set_log_match_id(id);
  return id;
}

}  // namespace

// A taken-over match runs with the primary's scene and match config, whatever the standby's own
// options said.
ServerOptions with_match_of(ServerOptions o, const MatchServer::Takeover* t) {
  if (t != nullptr) {
    o.scene = t->header.scene.name;
    o.match = t->header.config;
  }
  return o;
}

struct MatchServer::Impl {
  ServerOptions options;
  scene::SceneDef scene;
  match::Match match;
  std::uint64_t epoch = 1;  // +1 at every takeover (standby_server.h); fixed before run()
  // A claim of a higher epoch for this match (another server took it over while this one was
  // paused or cut off): set on a DDS thread, the tick loop then stops without another tick.
  std::atomic<std::uint64_t> fenced_by{0};
  // Orders two claims of one epoch (PrimaryClaim::server_id); a standby's own after a takeover.
  // Fixed before the transport starts: the claim handler reads it on a DDS thread.
  std::uint64_t server_id = random_server_id();
  std::unique_ptr<protocol::ServerTransport> transport;
  StandbyFeed standby_feed;  // tick entries and checkpoints for hot standbys
  admin::MetricsRegistry registry;
  ServerMetrics metrics{registry};
  std::unique_ptr<admin::AdminServer> admin;
  std::unique_ptr<matchlog::MatchLogWriter> log;  // null with --no-log
  std::uint64_t log_dropped_seen = 0, log_spilled_seen = 0, log_kf_dropped_seen = 0;
  // The log's first write error: log_failure is written once, before log_failed is set, and read
  // by the admin thread (/readyz degraded) only after it sees the flag.
  std::string log_failure;
  std::atomic<bool> log_failed{false};
  // World keyframes for the log: every keyframe interval the saver thread checkpoints the match
  // while the tick thread publishes and sleeps; the next tick (or shutdown) collects the bytes and
  // hands them to the writer (buffers swapped, not copied) before the match changes again.
  KeyframeSaver keyframe_saver{options.log_baselines};
  DurationStats keyframe_save, keyframe_wait, keyframe_append;

  match::Outbox outbox;
  ClientLedger ledger;
  // The whole match, the stats topic's window, and the progress line's window.
  DurationStats tick_all, tick_window, tick_progress;
  PhaseStats phases;  // per named phase, for the summary
  std::atomic<bool> stop_requested{false};
  std::atomic<bool> ready{false};
  Clock::time_point started{};
  Clock::time_point last_progress{};
  double wall_seconds = 0.0;
  std::uint64_t snapshot_bytes_at_last_progress = 0;  // for the progress line's rate
  std::uint64_t push_events_total = 0;
  std::uint64_t joins_foreign_total = 0;
  // Refused on DDS listener threads (the parameter-change gate), read by the tick thread.
  std::atomic<std::uint64_t> param_not_operator_total{0};
  std::uint64_t participants_refused_logged = 0;
  bool operators_allowed = false;  // --security (access control decides) or --allow-anonymous-operator
  std::uint64_t poses_total = 0;
  double view_error_max_m = 0.0;
  bool finished = false;
  std::unique_ptr<TickSchedule> schedule;
  // Why the match ended (summary): duration, signal, empty, routed, stopped. Set by whoever asks
  // first.
  std::mutex end_mutex;
  std::string end_reason;
  // --end-when-empty: a first player joined; since when nobody is connected.
  bool ever_joined = false;
  HeldFor empty_for;
  // --end-when-routed: since when a side has been routed.
  HeldFor routed_for;
  AgonesProbe agones_probe;
  std::unique_ptr<AgonesSdk> agones;

  void request_end(const char* reason) {
    {
      std::lock_guard<std::mutex> lock(end_mutex);
      if (end_reason.empty()) end_reason = reason;
    }
    stop_requested.store(true);
  }
  void check_empty(Clock::time_point now);
  void check_routed(Clock::time_point now);

  Impl(const ServerOptions& given, Takeover* takeover)
      : options(with_match_of(given, takeover)),
        scene(takeover ? takeover->header.scene : load_scaled_scene(options)),
        match(scene, options.match, takeover ? takeover->header.match_id : make_match_id(scene.name)),
        transport(takeover ? std::move(takeover->transport) : std::make_unique<protocol::ServerTransport>(transport_options(options))),
        standby_feed(scene, options.match, match.match_info().match_id),
        operators_allowed(options.allow_anonymous_operator || !options.security_dir.empty()) {
    const ServerOptions& o = options;
    if (takeover) resume(*takeover);
    if (o.admin_port >= 0) {
      admin::AdminServerOptions ao;
      ao.bind_address = o.admin_bind;
      ao.port = static_cast<std::uint16_t>(o.admin_port);
      ao.degraded = [this] {
        return log_failed.load(std::memory_order_acquire) ? "match log stopped: " + log_failure : std::string();
      };
      try {
        admin = std::make_unique<admin::AdminServer>(registry, [this] { return ready.load(); }, ao);
      } catch (const std::exception& e) {
        // A takeover must not lose the match for its admin endpoint (the port the standby had
        // may have been taken in between): it hosts without one.
        if (!takeover) throw;
        spdlog::error("took over without an admin endpoint: {}", e.what());
      }
    }
    if (takeover) {
      log = std::move(takeover->log);  // the standby's log goes on (null: it had none)
    } else if (!o.log_file.empty()) {
      const std::string path =
          o.log_file == "auto" ? o.log_dir + "/" + match.match_info().match_id + ".tlog" : o.log_file;
      matchlog::WriterOptions wo;
      wo.keyframe_snapshot_baselines = o.log_baselines;
      wo.keyframe_interval_ticks = o.log_keyframe_ticks;
      log = std::make_unique<matchlog::MatchLogWriter>(path, wo);
      matchlog::LogHeader h;
      h.match_id = match.match_info().match_id;
      h.scene = scene;
      h.config = o.match;
      log->begin(h);
      spdlog::info("match log: {} (verify with: throng-replay verify {})", path, path);
    }
  }

  // The DDS participant goes first: its listener threads call into members declared after it
  // (the standby feed, the operator gate's counters).
  ~Impl() { transport.reset(); }

  void resume(Takeover& t);
  void on_param_update(protocol::ParamUpdate&& u);
  void publish_outbox();
  void publish_stats(const match::TickReport& report);
  void run_tick(Clock::time_point woke);
  void log_progress(Clock::time_point now);
  void check_log();
  void finish_keyframe();
};

// A standby's takeover: the match as it followed it, each connected client's snapshot channel open
// again (in the partition the client reads) so its snapshots continue from the next tick, the
// clients in the summary.
void MatchServer::Impl::resume(Takeover& t) {
  set_log_match_id(t.header.match_id);
  if (!transport) throw std::runtime_error("takeover without a transport");
  match.restore_checkpoint(t.checkpoint);  // with the primary's snapshot baselines
  epoch = t.epoch;
  if (t.server_id != 0) server_id = t.server_id;
  standby_feed.set_epoch(epoch);
  for (const match::ClientSummary& c : match.clients()) {
    transport->open_client_channel(c.client_id, c.partition);
    ledger.joined(match::ClientEvent{match::ClientEvent::Kind::joined, c.client_id, c.entity, c.partition, c.name, 0, 0},
                  c.joined_tick);
  }
  spdlog::warn("took over match {} at tick {} as epoch {}: {} clients keep their ids and entities", t.header.match_id,
               match.tick_index(), epoch, match.client_count());
}

// The operator gate, on a DDS listener thread. With --security only identities granted the
// operator permission can write ParamUpdate at all (DDS access control refuses other writers), so
// whatever arrives is an operator's; without Security every participant looks alike, and changes
// pass only with --allow-anonymous-operator. A refused change never reaches the match (nothing to
// log, nothing to re-simulate) and is answered at once.
void MatchServer::Impl::on_param_update(protocol::ParamUpdate&& u) {
  if (operators_allowed) {
    match.inputs().push(std::move(u));
    return;
  }
  const std::uint64_t n = ++param_not_operator_total;
  if (n <= 10 || (n & (n - 1)) == 0)  // the first ten, then at powers of two: a flood must not flood the log
    spdlog::warn("parameter change {} refused: not an operator (run with --security and an operator identity, or "
                 "--allow-anonymous-operator for development); {} refused so far",
                 u.request_id, n);
  protocol::ParamReply reply;
  reply.request_id = u.request_id;
  reply.ok = false;
  reply.error = "not an operator";
  transport->publish_param_reply(reply);
}

// Collects the keyframe the saver thread took after the previous tick and appends it to the log.
// Must run before anything mutates the match (the save reads it).
void MatchServer::Impl::finish_keyframe() {
  KeyframeSaver::Finished k;
  if (!keyframe_saver.finish(k)) return;
  const auto a0 = Clock::now();
  log->append_keyframe_swap(k.tick, *k.bytes);  // O(1): buffers are swapped, not copied
  keyframe_save.add(k.save_seconds);
  keyframe_wait.add(k.waited_seconds);
  keyframe_append.add(seconds_between(a0, Clock::now()));
}

// Once a second: the log writer never blocks the tick, so a slow disk shows up here, loudly.
void MatchServer::Impl::check_log() {
  const matchlog::WriterStats s = log->stats();
  metrics.log_backlog_ticks.set(static_cast<double>(s.backlog_ticks));
  metrics.log_bytes.set(static_cast<double>(s.bytes_written));
  if (!s.io_error.empty() && !log_failed.load(std::memory_order_relaxed)) {
    // Once: the writer stops at its first error, so every later tick is dropped for the same cause.
    log_failure = s.io_error;
    log_failed.store(true, std::memory_order_release);
    metrics.log_write_errors.inc();
    spdlog::error("match log: {}; the match goes on without a log from here (the file verifies up to its last "
                  "complete block)", s.io_error);
  }
  if (s.ticks_dropped > log_dropped_seen) {
    metrics.log_ticks_dropped.inc(s.ticks_dropped - log_dropped_seen);
    if (!log_failed.load(std::memory_order_relaxed)) {
      spdlog::error("match log: {} ticks dropped so far (the disk is too slow); the log has a gap", s.ticks_dropped);
    }
    log_dropped_seen = s.ticks_dropped;
  }
  if (s.keyframes_dropped > log_kf_dropped_seen) {
    metrics.log_keyframes_dropped.inc(s.keyframes_dropped - log_kf_dropped_seen);
    spdlog::warn("match log: {} world keyframes skipped so far (the writer was still busy with the previous one); "
                 "seeking in this log will re-simulate further", s.keyframes_dropped);
    log_kf_dropped_seen = s.keyframes_dropped;
  }
  if (s.spilled_ticks > log_spilled_seen) {
    spdlog::warn("match log: the disk is behind the match ({} ticks waiting to be written)", s.backlog_ticks);
    log_spilled_seen = s.spilled_ticks;
  }
}

MatchServer::MatchServer(const ServerOptions& options) : impl_(std::make_unique<Impl>(options, nullptr)) {}
MatchServer::MatchServer(const ServerOptions& options, Takeover&& takeover)
    : impl_(std::make_unique<Impl>(options, &takeover)) {}
MatchServer::~MatchServer() = default;

void MatchServer::request_stop() { impl_->request_end("stopped"); }

// --end-when-empty: once a first player joined, the match ends when nobody has been connected for
// the configured time (a fleet's server must not idle forever after its players left).
// --end-when-routed: a side whose every NPC group keeps retreating for the configured time has lost.
void MatchServer::Impl::check_routed(Clock::time_point now) {
  if (options.end_when_routed_s <= 0.0 || finished) return;
  const std::optional<std::uint8_t> routed = match.routed_faction();
  switch (routed_for.update(routed.has_value(), now, options.end_when_routed_s)) {
    case HeldFor::State::ended:
      spdlog::info("no side is routed any more");
      break;
    case HeldFor::State::began:
      spdlog::info("faction {} is routed (every group retreating): the match ends in {} s unless it rallies", *routed,
                   options.end_when_routed_s);
      break;
    case HeldFor::State::elapsed:
      spdlog::info("faction {} routed for {} s: ending the match", *routed, options.end_when_routed_s);
      request_end("routed");
      break;
    case HeldFor::State::off:
    case HeldFor::State::holding:
      break;
  }
}

void MatchServer::Impl::check_empty(Clock::time_point now) {
  if (options.end_when_empty_s <= 0.0 || finished) return;
  const bool empty = match.client_count() == 0;
  ever_joined = ever_joined || !empty;
  switch (empty_for.update(ever_joined && empty, now, options.end_when_empty_s)) {
    case HeldFor::State::began:
      spdlog::info("every player has left: the match ends in {} s unless one joins", options.end_when_empty_s);
      break;
    case HeldFor::State::elapsed:
      spdlog::info("nobody connected for {} s: ending the match", options.end_when_empty_s);
      request_end("empty");
      break;
    case HeldFor::State::off:
    case HeldFor::State::ended:
    case HeldFor::State::holding:
      break;
  }
}

protocol::TransportCounters MatchServer::transport_counters() const { return impl_->transport->counters(); }

std::uint16_t MatchServer::admin_port() const { return impl_->admin ? impl_->admin->port() : 0; }

void MatchServer::Impl::publish_outbox() {
  // Snapshots were already published by the match's workers through the sink (run()): only the
  // bookkeeping is left, on this thread. Before the client events:
  // a client that joined this tick had no channel yet, so its first snapshot went nowhere.
  for (std::size_t i = 0; i < outbox.snapshot_count; ++i) {
    const auto& s = outbox.snapshots[i];
    ledger.snapshot_published(s.client_id, s.x.size());
  }

  for (const auto& e : outbox.client_events) {
    switch (e.kind) {
      case match::ClientEvent::Kind::joined:
        transport->open_client_channel(e.client_id, e.partition);
        ledger.joined(e, match.tick_index());
        spdlog::info("client {} '{}' joined: controls entity {} (partition {})", e.client_id, e.name, e.entity, e.partition);
        break;
      case match::ClientEvent::Kind::left:
      case match::ClientEvent::Kind::timed_out:
        transport->close_client_channel(e.client_id);
        ledger.departed(e, match.tick_index());
        spdlog::info("client {} '{}' {}: entity {} handed back to the AI", e.client_id, e.name,
                     e.kind == match::ClientEvent::Kind::left ? "left" : "timed out (no command)", e.entity);
        break;
    }
  }
  // The contacts debug channel (server/match/src/match_contacts.cpp): granted clients only.
  for (std::size_t i = 0; i < outbox.contacts_count; ++i) transport->publish_contacts(outbox.contacts[i]);
  for (const auto& r : outbox.join_replies) {
    transport->publish_join_reply(r);
    if (r.result != protocol::JoinResult::accepted && r.result != protocol::JoinResult::left)
      spdlog::warn("join refused ({}): {}", protocol::to_string(r.result), r.reason);
  }
  for (const auto& r : outbox.param_replies) {
    transport->publish_param_reply(r);
    if (r.ok) spdlog::info("operator change {} applied at tick {} (param version {})", r.request_id, r.tick, r.param_version);
    else spdlog::warn("operator change {} rejected: {}", r.request_id, r.error);
  }
  if (outbox.match_info_changed) transport->publish_match_info(match.match_info());
}

void MatchServer::Impl::publish_stats(const match::TickReport& report) {
  protocol::ServerStats st;
  st.tick = report.tick;
  st.tick_hz = options.match.tick_hz;
  st.clients = match.client_count();
  st.bodies = static_cast<std::uint32_t>(match.world().pos_x().size());
  st.tick_ms_p50 = static_cast<float>(tick_window.quantile(0.5) * 1e3);
  st.tick_ms_p99 = static_cast<float>(tick_window.quantile(0.99) * 1e3);
  st.tick_ms_max = static_cast<float>(tick_window.max() * 1e3);
  st.overruns = schedule->overruns();
  st.commands_accepted = match.commands_accepted_total();
  for (auto n : match.rejected_by_reason()) st.commands_rejected += n;
  const auto c = transport->counters();
  st.snapshot_bytes = c.snapshot_bytes;
  st.snapshot_samples = c.snapshot_samples;
  st.push_events = push_events_total;
  st.state_hash = report.state_hash;
  st.state = finished ? protocol::MatchState::ended : protocol::MatchState::running;
  transport->publish_stats(st);
  tick_window.reset();
}

void MatchServer::Impl::run_tick(Clock::time_point woke) {
  if (log) finish_keyframe();  // first: begin_shutdown() and tick() mutate the match
  if (fenced_by.load() != 0) {  // replaced while the keyframe was collected: not one more tick
    finished = true;
    return;
  }
  const bool stopping = stop_requested.load();
  if (stopping) match.begin_shutdown();  // this tick already refuses joins and says "ended"

  schedule->begin_tick(woke);
  const match::TickReport& report = match.tick(outbox);
  const std::uint8_t log_flags = stopping ? matchlog::kTickShutdownBegan : 0;
  if (log) log->append_tick(report.tick, match.last_inputs(), report.state_hash, log_flags);
  standby_feed.after_tick(match, report.tick, report.state_hash, log_flags, *transport);
  if (log && log->keyframe_interval_ticks() > 0 && report.tick % log->keyframe_interval_ticks() == 0)
    keyframe_saver.start(match, report.tick);  // runs beside publish_outbox (both only read the match)
  const auto published_at = Clock::now();
  publish_outbox();
  const auto done = Clock::now();
  const bool overrun = schedule->end_tick(done);

  const double tick_s = seconds_between(woke, done);
  tick_all.add(tick_s);
  tick_window.add(tick_s);
  tick_progress.add(tick_s);
  phases.add(report, seconds_between(published_at, done));
  push_events_total += report.push_events;
  poses_total += report.snapshot_poses;
  view_error_max_m = std::max(view_error_max_m, report.view_error_max_m);

  // Metrics: no allocation (atomics; a histogram takes its own short lock).
  metrics.ticks.inc();
  if (overrun) metrics.overruns.inc();
  metrics.tick_seconds.observe(tick_s);
  metrics.phase_seconds_step.observe(report.step_us * 1e-6);
  metrics.phase_seconds_publish.observe(seconds_between(published_at, done));
  metrics.clients.set(match.client_count());
  metrics.bodies.set(static_cast<double>(match.world().pos_x().size()));
  metrics.joins_accepted.inc(report.joins_accepted);
  metrics.joins_refused.inc(report.joins_refused);
  metrics.joins_foreign.inc(report.joins_foreign);
  if (report.joins_foreign > 0) {
    const std::uint64_t before = joins_foreign_total;
    joins_foreign_total += report.joins_foreign;
    // Logged when the total reaches 1, 2, 4, 8 ...: a flood must not flood the log.
    if (std::bit_width(before) != std::bit_width(joins_foreign_total))
      spdlog::warn("join/leave requests for clients another participant owns ignored (foreign_participant): {} so far",
                   joins_foreign_total);
  }
  metrics.param_not_operator.raise_to(param_not_operator_total.load());
  metrics.leaves.inc(report.leaves);
  metrics.timeouts.inc(report.timeouts);
  metrics.commands_accepted.inc(report.commands_accepted);
  metrics.param_updates_applied.inc(report.param_updates_applied);
  metrics.param_updates_rejected.inc(report.param_updates_rejected);
  metrics.push_events.inc(report.push_events);
  metrics.observe_step(report.world);
  metrics.contacts_refused.inc(report.contacts_refused);
  metrics.snapshot_poses.inc(report.snapshot_poses);
  metrics.view_error_max_m.set(report.view_error_max_m);
  metrics.state_hash_low32.set(static_cast<double>(report.state_hash & 0xFFFF'FFFFu));
  // Totals kept elsewhere (match, transport, schedule) are mirrored into the counters.
  const auto& by_reason = match.rejected_by_reason();
  for (std::size_t i = 0; i < by_reason.size(); ++i) metrics.commands_rejected[i]->raise_to(by_reason[i]);
  metrics.input_queue_dropped.raise_to(match.inputs().dropped());
  const auto c = transport->counters();
  metrics.snapshot_samples.raise_to(c.snapshot_samples);
  metrics.snapshot_bytes.raise_to(c.snapshot_bytes);
  metrics.other_samples.raise_to(c.other_samples);
  metrics.other_bytes.raise_to(c.other_bytes);
  metrics.contacts_samples.raise_to(c.contacts_samples);
  metrics.contacts_bytes.raise_to(c.contacts_bytes);
  metrics.participants_refused.raise_to(c.participants_refused);
  metrics.skipped_ticks.raise_to(schedule->skipped());

  if (stopping) finished = true;
  if (report.tick % options.match.tick_hz == 0 || finished) {
    publish_stats(report);
    // Logged at 1, 2, 4, 8 ... refusals: a stranger retries about once a second.
    if (c.participants_refused > 0 && c.participants_refused >= 2 * participants_refused_logged) {
      spdlog::warn("DDS Security refused {} authentication attempt(s) so far: a participant with a certificate of "
                   "another CA, an expired certificate or permissions that do not verify (throng-pki check DIR "
                   "tells which of ours is wrong)", c.participants_refused);
      participants_refused_logged = c.participants_refused;
    }
    if (log) check_log();
  }
  if (done - last_progress >= std::chrono::seconds(10)) log_progress(done);
  check_empty(done);
  check_routed(done);
  agones_probe.players.store(match.client_count());
  agones_probe.ticks.store(report.tick);
  if (options.tick_hook_for_tests) options.tick_hook_for_tests(report.tick);
  ready.store(!finished);
}

void MatchServer::Impl::log_progress(Clock::time_point now) {
  const double window_s = seconds_between(last_progress, now);
  last_progress = now;
  const auto c = transport->counters();
  // Both the match so far and the last window: a soak compares windows (deploy/soak.sh reads them).
  spdlog::info("tick {} | clients {} | tick p50 {:.2f} ms p99 {:.2f} ms max {:.2f} ms | last {:.0f} s: p50 {:.2f} ms "
               "p99 {:.2f} ms | overruns {} | snapshots {:.0f} kbit/s total",
               match.tick_index(), match.client_count(), tick_all.quantile(0.5) * 1e3, tick_all.quantile(0.99) * 1e3,
               tick_all.max() * 1e3, window_s, tick_progress.quantile(0.5) * 1e3, tick_progress.quantile(0.99) * 1e3,
               schedule->overruns(),
               window_s > 0 ? static_cast<double>(c.snapshot_bytes - snapshot_bytes_at_last_progress) * 8.0 / 1000.0 / window_s : 0.0);
  snapshot_bytes_at_last_progress = c.snapshot_bytes;
  tick_progress.reset();
}

int MatchServer::run(bool handle_signals) {
  Impl& m = *impl_;
  boost::asio::io_context io;
  boost::asio::steady_timer timer(io);
  boost::asio::signal_set signals(io);
  if (handle_signals) {
    signals.add(SIGINT);
    signals.add(SIGTERM);
    signals.async_wait([&](const boost::system::error_code& ec, int signo) {
      if (ec) return;
      spdlog::info("{} received: finishing the current tick and ending the match", signo == SIGINT ? "SIGINT" : "SIGTERM");
      m.request_end("signal");
    });
  }

  m.transport->start(protocol::ServerTransport::Handlers{
      [&m](protocol::JoinRequest&& r) { m.match.inputs().push(std::move(r)); },
      [&m](protocol::Command&& c) { m.match.inputs().push(std::move(c)); },
      [&m](protocol::ParamUpdate&& u) { m.on_param_update(std::move(u)); },
      [&m](protocol::StandbyRequest&& r) { m.standby_feed.on_request(std::move(r)); },
      [&m, id = m.match.match_info().match_id](protocol::PrimaryClaim&& c) {
        const bool above = c.epoch > m.epoch || (c.epoch == m.epoch && c.server_id > m.server_id);
        if (c.match_id == id && above && m.fenced_by.load() == 0) {
          // Not request_end: a stop request would make the next tick a shutdown tick, whose
          // "ended" reaches the new primary's clients. The tick loop checks fenced_by instead.
          {
            std::lock_guard<std::mutex> lock(m.end_mutex);
            if (m.end_reason.empty()) m.end_reason = "fenced";
          }
          m.fenced_by.store(c.epoch);
        }
      },
  });
  m.transport->publish_primary_claim(
      protocol::PrimaryClaim{m.match.match_info().match_id, m.epoch, m.match.tick_index(), m.server_id});
  m.transport->publish_match_info(m.match.match_info());
  // Publish each snapshot from the worker that built it (the transport is thread-safe), so
  // building and publishing overlap across clients.
  m.match.set_snapshot_sink([&m](const protocol::Snapshot& s) { m.transport->publish_snapshot(s); });

  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / m.options.match.tick_hz));
  m.started = Clock::now();
  m.last_progress = m.started;
  m.schedule = std::make_unique<TickSchedule>(period, m.options.max_catchup_ticks, m.started);
  const auto end_at = m.options.duration_s > 0
                          ? m.started + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(m.options.duration_s))
                          : Clock::time_point::max();
  if (!m.options.security_dir.empty())
    spdlog::info("DDS Security on: identity {}/server; unauthenticated participants are refused, parameter changes "
                 "only from operator identities", m.options.security_dir);
  else
    spdlog::log(m.options.loopback_only ? spdlog::level::info : spdlog::level::warn,
                "DDS Security off: any participant on the domain can read every snapshot; clients are bound to the "
                "participant that joined them{}",
                m.options.allow_anonymous_operator ? ", and ANY participant may change parameters (--allow-anonymous-operator)"
                                                   : "; parameter changes are refused");
  const bool udp_listen = m.options.listen.rfind("udp://", 0) == 0;
  spdlog::info("match {} on DDS domain {} ({}): scene '{}', {} bodies, {} Hz, up to {} clients{}", m.match.match_info().match_id,
               m.options.domain,
               !m.options.listen.empty()
                   ? fmt::format("{}, listening on {}{}{}", udp_listen ? "UDP across NAT" : "TCP", m.options.listen,
                                 m.options.public_address.empty() ? "" : ", clients told " + m.options.public_address,
                                 udp_listen ? "" : "; no hot standby can follow it over TCP")
                   : (m.options.loopback_only ? "127.0.0.1 only" : "default network"),
               m.scene.name,
               m.match.world().pos_x().size(), m.options.match.tick_hz, m.options.match.max_clients,
               m.options.duration_s > 0 ? fmt::format(", for {} s", m.options.duration_s) : std::string(", until SIGINT/SIGTERM"));
  if (m.admin) spdlog::info("admin listening on {}:{} (/healthz /readyz /metrics)", m.options.admin_bind, m.admin->port());
  if (m.options.agones_port != 0) {
    AgonesOptions ao;
    ao.port = m.options.agones_port;
    ao.health_interval = std::chrono::milliseconds(m.options.agones_health_interval_ms);
    ao.retry_interval = std::min(ao.retry_interval, ao.health_interval);
    spdlog::info("Agones SDK on 127.0.0.1:{}: ready after the first tick, health every {} ms while ticks run, shutdown "
                 "at the end", ao.port, ao.health_interval.count());
    m.agones = std::make_unique<AgonesSdk>(ao, m.agones_probe);
  }

  std::function<void()> arm = [&] {
    timer.expires_at(m.schedule->next_deadline());
    timer.async_wait([&](const boost::system::error_code& ec) {
      if (ec) return;
      const auto woke = Clock::now();
      if (m.fenced_by.load() != 0) {
        // Replaced: not one more tick, not even the shutdown tick (its "ended" would tell the
        // clients of the new primary that their match is over).
        m.finished = true;
        signals.cancel();
        return;
      }
      if (woke >= end_at) m.request_end("duration");
      m.run_tick(woke);
      if (m.finished) {
        signals.cancel();
        return;
      }
      arm();
    });
  };
  auto trimmer = MemoryTrimmer::every_seconds(m.options.trim_memory_s);
  arm();
  io.run();
  log_and_stop(trimmer);

  if (m.fenced_by.load() != 0)
    spdlog::error("match {} is hosted by another server now (epoch {}, this server's {}): this server was replaced (it "
                  "was paused or cut off, or another standby took over at the same moment) and stops hosting it at "
                  "tick {}", m.match.match_info().match_id,
                  m.fenced_by.load(), m.epoch, m.match.tick_index());
  m.transport->flush(std::chrono::seconds(2));  // clients must hear "ended" before we vanish
  if (m.log) {
    try {
      m.finish_keyframe();  // the last tick may have been a keyframe tick
      m.log->close();
      const auto ls = m.log->stats();
      spdlog::info("match log closed: {} ticks, {} bytes ({:.0f} bytes/tick)", ls.ticks_written, ls.bytes_written,
                   ls.ticks_written ? static_cast<double>(ls.bytes_written) / static_cast<double>(ls.ticks_written) : 0.0);
      if (ls.keyframes_appended > 0)
        spdlog::info("match log keyframes: {} written, {} skipped, {} bytes in the file ({} raw); save_checkpoint on the "
                     "saver thread p50 {:.2f} ms p99 {:.2f} ms max {:.2f} ms; the tick thread waited for it p99 {:.3f} ms "
                     "max {:.3f} ms and appended p99 {:.3f} ms max {:.3f} ms",
                     ls.keyframes_written, ls.keyframes_dropped, ls.keyframe_bytes, ls.keyframe_raw_bytes,
                     m.keyframe_save.quantile(0.5) * 1e3, m.keyframe_save.quantile(0.99) * 1e3, m.keyframe_save.max() * 1e3,
                     m.keyframe_wait.quantile(0.99) * 1e3, m.keyframe_wait.max() * 1e3,
                     m.keyframe_append.quantile(0.99) * 1e3, m.keyframe_append.max() * 1e3);
    } catch (const std::exception& e) {
      // A write error was reported when it happened (check_log); say it once, not again here.
      if (m.log_failed.load()) spdlog::info("match log closed after its write error (reported above)");
      else spdlog::error("match log: {}", e.what());
    }
  }
  if (m.agones) {
    // After the log is closed and "ended" went out: Agones may now tear the pod down.
    m.agones_probe.ended.store(true);
    if (!m.agones->wait_shutdown_sent(std::chrono::seconds(10)))
      spdlog::error("Agones: /shutdown not acknowledged within 10 s; exiting anyway");
    m.agones.reset();
  }
  m.wall_seconds = seconds_between(m.started, Clock::now());
  m.ledger.update_commands(m.match);
  m.ready.store(false);
  const nlohmann::json s = summary();
  if (!m.options.summary_json.empty()) {
    std::ofstream f(m.options.summary_json);
    f << s.dump(2) << "\n";
    if (!f) spdlog::error("cannot write the summary to {}", m.options.summary_json);
  }
  std::fputs(format_summary(s).c_str(), stdout);
  std::fflush(stdout);
  if (m.standby_feed.stats().syncs_sent > 0)
    spdlog::info("hot standby: {} tick entries published, {} checkpoints sent", m.standby_feed.stats().entries_published,
                 m.standby_feed.stats().syncs_sent);
  const int code = m.fenced_by.load() != 0 ? kExitFenced : 0;
  spdlog::info("match ended after {} ticks; exit {}", m.match.tick_index(), code);
  return code;
}

nlohmann::json MatchServer::summary() const {
  const Impl& m = *impl_;
  SummaryInputs in{m.match, m.ledger, m.tick_all, m.phases, *m.schedule, m.transport->counters(), 0.0, 0, 0, 0.0, {}};
  in.wall_seconds = m.wall_seconds;
  in.push_events = m.push_events_total;
  in.poses = m.poses_total;
  in.view_error_max_m = m.view_error_max_m;
  in.joins_foreign = m.joins_foreign_total;
  in.param_not_operator = m.param_not_operator_total.load();
  in.scene_name = m.scene.name;
  in.end_reason = m.end_reason;
  nlohmann::json j = make_summary(in);
  j["epoch"] = m.epoch;
  return j;
}

}  // namespace throng::server
