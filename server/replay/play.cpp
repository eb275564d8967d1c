// throng-replay play: re-publish a logged match over DDS at tick_hz x speed, so bots and viewers
// watch it as if live (topics and order: play_session.h; watchers: play_watchers.h).
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <memory>
#include <thread>

#include <fmt/format.h>

#include "commands.h"
#include "open_log.h"
#include "play_session.h"
#include "throng/matchlog/log_player.h"
#include "throng/protocol/dds_transport.h"
#include "throng/protocol/security.h"
#include "throng/server/tick_schedule.h"

namespace throng::replay {

namespace {

using Clock = std::chrono::steady_clock;

std::atomic<int> g_signal{0};  // lock-free: safe to set from a signal handler
extern "C" void on_stop_signal(int signo) { g_signal.store(signo); }

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// One line on stderr: rewritten about once a second on a terminal, every 10 s otherwise.
class PlayProgress {
 public:
  PlayProgress(bool enabled, std::uint64_t last_tick, Clock::time_point start)
      : enabled_(enabled), tty_(isatty(STDERR_FILENO) == 1), last_(last_tick), printed_(start) {}
  void update(Clock::time_point now, std::uint64_t tick, double actual_speed, std::size_t watchers, std::uint64_t mismatches) {
    if (!enabled_ || now - printed_ < (tty_ ? std::chrono::seconds(1) : std::chrono::seconds(10))) return;
    printed_ = now;
    shown_ = true;
    fmt::print(stderr, "{}play: tick {}/{} ({:.0f}%)  speed {:.2f}x  watchers {}  hash mismatches {}{}", tty_ ? "\r" : "", tick,
               last_, 100.0 * static_cast<double>(tick) / static_cast<double>(last_), actual_speed, watchers, mismatches,
               tty_ ? "   " : "\n");
    std::fflush(stderr);
  }
  void finish() {
    if (enabled_ && tty_ && shown_) fmt::print(stderr, "\n");
    shown_ = false;
  }

 private:
  bool enabled_, tty_;
  std::uint64_t last_;
  Clock::time_point printed_;
  bool shown_ = false;  // a rewriting line is on the terminal: finish() ends it
};

// Everything about the log that is wrong before a tick is played: exit 2 with one sentence.
bool check_playable(const PlayOptions& o, const matchlog::LogPlayer& player) {
  if (!(std::isfinite(o.speed) && o.speed >= 0.1 && o.speed <= 16.0)) {
    fmt::print(stderr, "throng-replay play: --speed must be between 0.1 and 16, got {}\n", o.speed);
    return false;
  }
  if (player.last_tick() == 0) {
    fmt::print(stderr, "throng-replay play: {}: the log has no playable ticks{}\n", o.log,
               player.scan().problem.empty() ? "" : " (" + player.scan().problem + ")");
    return false;
  }
  if (o.from < 1 || o.from > player.last_tick()) {
    fmt::print(stderr, "throng-replay play: --from {} is outside the log: it can play ticks 1..{}\n", o.from, player.last_tick());
    return false;
  }
  return true;
}

void print_notes(const matchlog::LogPlayer& player) {
  const auto& h = player.header();
  const auto& s = player.scan();
  if (h.build_id != matchlog::default_build_id())
    fmt::print(stderr, "note: the log was written by '{}', this is '{}': if the simulation changed in between, the "
                       "re-simulation may differ from what was played (every tick's hash is checked)\n",
               h.build_id, matchlog::default_build_id());
  if (player.last_tick() < s.last_tick || s.end == matchlog::LogEnd::corrupt)
    fmt::print(stderr, "note: only ticks 1..{} can be played: {}\n", player.last_tick(),
               s.problem.empty() ? "the writer dropped ticks after it" : s.problem);
  else if (s.end != matchlog::LogEnd::closed)
    fmt::print(stderr, "note: {}\n", s.problem);
}

enum class StopReason { end_of_log, signal, strict_mismatch };

}  // namespace

int run_play(const PlayOptions& o) {
  const auto player = open_log<matchlog::LogPlayer>("play", o.log);
  if (!player) return kExitBadInput;
  if (!check_playable(o, *player)) return kExitBadInput;
  print_notes(*player);
  const auto& h = player->header();
  const double hz = static_cast<double>(player->tick_hz()) * o.speed;

  std::unique_ptr<protocol::ServerTransport> transport;
  try {
    protocol::TransportOptions t{o.domain, !o.network, "throng-replay", std::nullopt};
    if (!o.security_dir.empty()) t.security = protocol::security_files(o.security_dir, protocol::kServerIdentity);
    if (!o.listen.empty()) t.listen_endpoint = protocol::parse_endpoint(o.listen);
    transport = std::make_unique<protocol::ServerTransport>(t);
  } catch (const std::exception& e) {
    fmt::print(stderr, "throng-replay play: cannot open DDS domain {}: {}\n", o.domain, e.what());
    return kExitBadInput;
  }
  WatcherOptions wo;
  wo.max_watchers = o.max_watchers;
  wo.timeout = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.watcher_timeout_s));
  PlaySession session(*player, *transport, wo);

  install_signal_handlers();
  // The seek runs before anything is published: a watcher never sees the fast-forward.
  const matchlog::SeekResult first_seek = player->seek(o.from - 1);
  session.start();
  session.after_seek(first_seek);
  fmt::print(stderr, "playing {} (match {}, scene '{}', ticks {}..{} at {} Hz x {} = {:.1f} ticks/s) on DDS domain {} ({}){}\n",
             o.log, h.match_id, h.scene.name, o.from, player->last_tick(), player->tick_hz(), o.speed, hz, o.domain,
             o.network ? "default network" : "127.0.0.1 only", o.loop ? ", looping" : "");
  if (first_seek.ticks_simulated > 0)
    fmt::print(stderr, "seeked to tick {} in {:.0f} ms ({} ticks re-simulated)\n", first_seek.tick, first_seek.ms,
               first_seek.ticks_simulated);
  if (first_seek.keyframe_tick > 0 && !h.writer.keyframe_snapshot_baselines)
    fmt::print(stderr, "note: this log's keyframes hold no snapshot baselines (the server's default; --log-baselines keeps "
                       "them): snapshots were rebuilt from empty baselines at the keyframe of tick {}, so they are not byte "
                       "for byte what the server sent\n",
               first_seek.keyframe_tick);

  // Absolute deadlines, like the server's tick (TickSchedule): a late wake-up never becomes drift;
  // after a stall at most 3 ticks run back to back, and the lost time beyond is given up.
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / hz));
  const auto started = Clock::now();
  server::TickSchedule schedule(period, 3, started);
  PlayProgress progress(!o.quiet, player->last_tick(), started);
  std::uint64_t loops = 0;
  StopReason stop = StopReason::end_of_log;
  int signo = 0;
  double work_s = 0.0;
  bool warned_mismatch = false;

  for (;;) {
    if ((signo = g_signal.load()) != 0) {
      stop = StopReason::signal;
      break;
    }
    std::this_thread::sleep_until(schedule.next_deadline());
    if (g_signal.load() != 0) continue;  // stop before publishing another tick
    const auto woke = Clock::now();
    schedule.begin_tick(woke);
    if (!player->step()) {
      if (!o.loop) break;
      ++loops;
      session.after_seek(player->seek(o.from - 1));
      continue;
    }
    session.publish_tick(woke, work_s, schedule.overruns());
    if (session.last_tick_mismatched() && !warned_mismatch) {
      warned_mismatch = true;
      progress.finish();
      fmt::print(stderr,
                 "HASH MISMATCH at tick {}: this build does NOT reproduce the log (its state hash differs from the "
                 "logged one); what is published from here on is this build's re-simulation, not what the server "
                 "sent{}\n",
                 player->tick(), o.strict ? ". --strict: stopping" : ". Playing on (--strict stops here)");
    }
    const auto done = Clock::now();
    work_s = seconds(done - woke);
    schedule.end_tick(done);
    if (session.last_tick_mismatched() && o.strict) {
      stop = StopReason::strict_mismatch;
      break;
    }
    const double elapsed = seconds(done - started);
    progress.update(done, player->tick(), elapsed > 0 ? static_cast<double>(session.totals().ticks_played) / elapsed / player->tick_hz() : 0.0,
                    session.watcher_count(), session.totals().hash_mismatches);
  }
  progress.finish();
  const double wall = seconds(Clock::now() - started);
  session.end(schedule.overruns());

  const SessionTotals& t = session.totals();
  const WatcherTotals& w = session.watcher_totals();
  const auto c = transport->counters();
  const double played_rate = wall > 0 ? static_cast<double>(t.ticks_played) / wall : 0.0;
  fmt::print("throng-replay play summary\n");
  fmt::print("  log: {} (match {}, scene '{}', {} Hz)\n", o.log, h.match_id, h.scene.name, player->tick_hz());
  const char* stopped_by = stop == StopReason::end_of_log ? "the end of the log"
                           : stop == StopReason::strict_mismatch ? "a hash mismatch (--strict)"
                           : signo == SIGINT                  ? "SIGINT"
                                                              : "SIGTERM";
  fmt::print("  stopped by: {} at tick {}{}\n", stopped_by, player->tick(), loops ? fmt::format(" ({} loops)", loops) : "");
  fmt::print("  ticks played: {} in {:.2f} s = {:.2f} ticks/s (target {:.2f}: {:.4f} x; overruns {}, ticks' time given up {})\n",
             t.ticks_played, wall, played_rate, hz, hz > 0 ? played_rate / hz : 0.0, schedule.overruns(), schedule.skipped());
  if (t.hash_mismatches == 0)
    fmt::print("  hash mismatches: 0 (this build reproduces every played tick)\n");
  else
    fmt::print("  hash mismatches: {} (first at tick {}): THIS BUILD DOES NOT REPRODUCE THE LOG\n", t.hash_mismatches,
               t.first_mismatch_tick);
  fmt::print("  watchers: {} joined, {} refused, {} left, {} timed out; {} commands ignored, {} parameter updates refused{}\n",
             w.joined, w.refused, w.left, w.timed_out, w.commands_ignored, t.param_updates_refused,
             t.inputs_dropped ? fmt::format(", {} requests dropped (flood)", t.inputs_dropped) : "");
  fmt::print("  published: {} snapshots, {} bytes ({:.1f} kB/s); other topics {} samples, {} bytes\n", c.snapshot_samples,
             c.snapshot_bytes, wall > 0 ? static_cast<double>(c.snapshot_bytes) / wall / 1000.0 : 0.0, c.other_samples,
             c.other_bytes);
  std::fflush(stdout);

  if (t.hash_mismatches > 0) return kExitMismatch;
  // Reached the end of what could be played, but the log goes on past damage or a gap: as verify.
  const auto& s = player->scan();
  if (stop == StopReason::end_of_log && (player->last_tick() < s.last_tick || s.end == matchlog::LogEnd::corrupt)) return kExitDamaged;
  return kExitOk;
}

}  // namespace throng::replay
