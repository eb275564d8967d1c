#include "log_loop.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>

#include <fmt/format.h>

#include "display_host.h"
#include "page_server.h"
#include "throng/matchlog/log_player.h"
#include "throng/view/log_control.h"
#include "throng/view/log_frame.h"
#include "throng/view/match_json.h"
#include "throng/view/web_server.h"

namespace throng::view {

namespace {

using namespace std::chrono_literals;
using Clock = LogController::Clock;
using TimePoint = LogController::TimePoint;

// Filled by the web thread, drained by the loop.
class CommandQueue {
 public:
  static constexpr std::size_t kMax = 1024;  // a page flooding us: the oldest commands go

  void accept(const LogCommand& c) {
    {
      std::lock_guard lock(mutex_);
      if (queue_.size() >= kMax) queue_.pop_front();
      queue_.push_back(c);
    }
    wake_.notify_one();
  }
  void reject(InputError e) {
    std::lock_guard lock(mutex_);
    ++errors_[static_cast<std::size_t>(e)];
  }
  // Waits until a command arrives or `until`, then takes everything queued.
  std::deque<LogCommand> take(TimePoint until, std::array<std::uint64_t, kInputErrorCount>& errors) {
    std::unique_lock lock(mutex_);
    wake_.wait_until(lock, until, [&] { return !queue_.empty(); });
    errors = errors_;
    std::deque<LogCommand> out;
    out.swap(queue_);
    return out;
  }

 private:
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<LogCommand> queue_;
  std::array<std::uint64_t, kInputErrorCount> errors_{};
};

std::string mmss(double seconds) {
  const auto s = static_cast<std::uint64_t>(seconds);
  return fmt::format("{}:{:02}", s / 60, s % 60);
}

// The log to play, checked: null (after saying why) when it cannot be played from --from.
std::unique_ptr<matchlog::LogPlayer> open_player(const LogViewOptions& o) {
  std::unique_ptr<matchlog::LogPlayer> player;
  try {
    matchlog::PlayerOptions po;
    // The viewer reads the world, not snapshots: the cheap interest settings (replay.h) are enough.
    po.resim.exact_interest = false;
    // The contacts overlay reads the world's push events (the state hash does not depend on them).
    po.resim.record_push_events = true;
    player = std::make_unique<matchlog::LogPlayer>(o.log, po);
  } catch (const std::exception& e) {
    fmt::print(stderr, "throng-view: cannot play {}: {}\n", o.log, e.what());
    return nullptr;
  }
  const std::uint64_t last = player->last_tick();
  if (last == 0) {
    fmt::print(stderr, "throng-view: cannot play {}: the log holds no complete tick\n", o.log);
    return nullptr;
  }
  if (o.from > last) {
    fmt::print(stderr, "throng-view: --from {} is beyond the log's last playable tick {}\n", o.from, last);
    return nullptr;
  }
  if (!player->scan().problem.empty())
    fmt::print(stderr, "throng-view: {}: {}; playing ticks 0..{}\n", o.log, player->scan().problem, last);
  if (!player->scan().scene_hash_matches)
    fmt::print(stderr, "throng-view: the log's scene re-serialises differently in this build: the replay may diverge\n");
  return player;
}

// The replay loop: page commands in, the player stepped at the chosen speed, frames out. Each
// step of a turn is a method.
class LogViewLoop {
 public:
  LogViewLoop(const LogViewOptions& o, matchlog::LogPlayer& player, WebServer& web, CommandQueue& commands)
      : o_(o), player_(player), web_(web), commands_(commands), last_(player.last_tick()), hz_(player.tick_hz()),
        control_(LogTimeline{last_, hz_}, o.from, o.speed, !o.paused, Clock::now()) {}

  void run(const std::atomic<bool>& stop) {
    next_status_ = Clock::now() + 10s;
    while (!stop.load()) {
      apply_commands();
      TimePoint now = Clock::now();
      if (const auto seek = control_.take_seek()) now = seek_to(*seek);
      step_to_target(now);
      now = Clock::now();
      show_frame(now);
      report(now);
    }
  }

 private:
  // Frames: after the shown tick changes (at most ~45 a second, so 8x does not flood the page),
  // and every 250 ms regardless, so a page that connects while paused gets one.
  static constexpr auto kMinFrameGap = 22ms;
  static constexpr auto kHeartbeat = 250ms;
  static constexpr auto kStepBudget = 40ms;  // stepping per loop turn before the page hears from us again

  std::string fields(bool seeking) const {
    return control_.json_fields(player_.tick(), seeking) + fmt::format(R"(,"hash_ok":{})", player_.last_hash_matched());
  }
  void check_hash() {
    if (warned_hash_ || player_.last_hash_matched()) return;
    warned_hash_ = true;
    fmt::print(stderr, "throng-view: tick {} re-simulates to a different state hash than the log recorded: "
               "this build diverges from the one that played it; positions from here on may differ\n", player_.tick());
  }

  // Waits for the next tick due at this speed, a page command, or at least 50 ms; applies what came.
  void apply_commands() {
    const auto tick_period =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / (hz_ * control_.speed())));
    const TimePoint wake_at =
        Clock::now() + (control_.playing() ? std::clamp<Clock::duration>(tick_period, 2ms, 50ms) : Clock::duration(50ms));
    const auto got = commands_.take(wake_at, errors_);
    const TimePoint now = Clock::now();
    for (const auto& c : got) {
      if (c.kind == LogCommand::Kind::focus) {
        focus_ = c.id;
      } else if (c.kind == LogCommand::Kind::contacts) {
        contacts_ = c.on ? std::optional<ContactsView>(ContactsView{c.camera_x, c.camera_y}) : std::nullopt;
      } else {
        control_.apply(c, now);
      }
      dirty_ = true;
    }
  }

  // Blocks for the seek (the page shows "seeking..." meanwhile); its duration is not play time.
  TimePoint seek_to(std::uint64_t tick) {
    web_.broadcast(timeline_json(fields(true)));
    const auto r = player_.seek(tick);
    check_hash();
    if (!o_.quiet && r.ms > 500)
      fmt::print(stderr, "throng-view: seek to tick {} took {:.1f} s ({} ticks re-simulated)\n", r.tick, r.ms / 1000.0,
                 r.ticks_simulated);
    const TimePoint now = Clock::now();
    control_.advance(now);
    control_.reached(player_.tick());
    dirty_ = true;
    return now;
  }

  // Steps toward the tick due now, for at most kStepBudget.
  void step_to_target(TimePoint now) {
    const std::uint64_t target = control_.advance(now);
    if (target < player_.tick()) player_.seek(target);  // cannot happen without a seek; stay correct anyway
    const TimePoint step_until = now + kStepBudget;
    while (player_.tick() < target && Clock::now() < step_until) {
      if (!player_.step()) break;
      check_hash();
    }
    control_.reached(player_.tick());
  }

  void show_frame(TimePoint now) {
    const bool new_tick = player_.tick() != framed_tick_;
    if (!(((new_tick || dirty_) && now - last_frame_ >= kMinFrameGap) || now - last_frame_ >= kHeartbeat)) return;
    std::uint64_t errors_total = 0;
    for (auto e : errors_) errors_total += e;
    web_.broadcast(frames_.frame_json(player_.match(), fields(false), focus_, web_.sessions(), errors_total, contacts_));
    framed_tick_ = player_.tick();
    last_frame_ = now;
    dirty_ = false;
  }

  void report(TimePoint now) {
    report_rejections(errors_, reported_);
    if (o_.quiet || now < next_status_) return;
    next_status_ = now + 10s;
    fmt::print(stderr, "throng-view: replay tick {}/{} ({} / {})  {}  {:g}x  pages {}\n", player_.tick(), last_,
               mmss(static_cast<double>(player_.tick()) / hz_), mmss(static_cast<double>(last_) / hz_),
               control_.playing() ? "playing" : "paused", control_.speed(), web_.sessions());
  }

  const LogViewOptions& o_;
  matchlog::LogPlayer& player_;
  WebServer& web_;
  CommandQueue& commands_;
  const std::uint64_t last_;
  const std::uint32_t hz_;
  LogController control_;
  LogFrameBuilder frames_;
  std::uint32_t focus_ = 0;
  std::optional<ContactsView> contacts_;  // the overlay's camera while the page asks for contact pairs
  std::array<std::uint64_t, kInputErrorCount> errors_{}, reported_{};
  bool warned_hash_ = false;
  TimePoint last_frame_{};
  std::uint64_t framed_tick_ = ~0ull;
  bool dirty_ = true;
  TimePoint next_status_{};
};

}  // namespace

int run_log_view(const LogViewOptions& o, const std::atomic<bool>& stop) {
  // The log first: a file that cannot be played is reported before a port is taken.
  const std::unique_ptr<matchlog::LogPlayer> player = open_player(o);
  if (!player) return 2;
  CommandQueue commands;
  std::optional<WebServer> web;
  if (!open_page_server<LogCommand>(web, o.bind, o.port, o.web_root, parse_log_message, commands)) return 1;
  web->set_greeting(match_info_json(player->match().match_info(), "replay"));
  const std::uint64_t last = player->last_tick();
  fmt::print(stderr, "throng-view: replay of {} (match {}, {} ticks at {} Hz, {})\n", o.log, player->header().match_id,
             last, player->tick_hz(), mmss(static_cast<double>(last) / player->tick_hz()));
  fmt::print("view at http://{}:{}/\n", display_host(o.bind), web->port());
  std::fflush(stdout);
  if (o.from > 0) player->seek(o.from);
  LogViewLoop(o, *player, *web, commands).run(stop);
  web->stop();
  return 0;
}

}  // namespace throng::view
