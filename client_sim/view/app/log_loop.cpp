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

}  // namespace

int run_log_view(const LogViewOptions& o, const std::atomic<bool>& stop) {
  // The log first: a file that cannot be played is reported before a port is taken.
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
    return 2;
  }
  const std::uint64_t last = player->last_tick();
  const std::uint32_t hz = player->tick_hz();
  if (last == 0) {
    fmt::print(stderr, "throng-view: cannot play {}: the log holds no complete tick\n", o.log);
    return 2;
  }
  if (o.from > last) {
    fmt::print(stderr, "throng-view: --from {} is beyond the log's last playable tick {}\n", o.from, last);
    return 2;
  }
  if (!player->scan().problem.empty())
    fmt::print(stderr, "throng-view: {}: {}; playing ticks 0..{}\n", o.log, player->scan().problem, last);
  if (!player->scan().scene_hash_matches)
    fmt::print(stderr, "throng-view: the log's scene re-serialises differently in this build: the replay may diverge\n");

  CommandQueue commands;
  std::optional<WebServer> web;
  if (!open_page_server<LogCommand>(web, o.bind, o.port, o.web_root, parse_log_message, commands)) return 1;
  web->set_greeting(match_info_json(player->match().match_info(), "replay"));
  fmt::print(stderr, "throng-view: replay of {} (match {}, {} ticks at {} Hz, {})\n", o.log, player->header().match_id,
             last, hz, mmss(static_cast<double>(last) / hz));
  fmt::print("view at http://{}:{}/\n", display_host(o.bind), web->port());
  std::fflush(stdout);

  if (o.from > 0) player->seek(o.from);
  LogController control(LogTimeline{last, hz}, o.from, o.speed, !o.paused, Clock::now());
  LogFrameBuilder frames;
  std::uint32_t focus = 0;
  std::optional<ContactsView> contacts;  // the overlay's camera while the page asks for contact pairs
  std::array<std::uint64_t, kInputErrorCount> errors{}, reported{};
  bool warned_hash = false;
  // Frames: after the shown tick changes (at most ~45 a second, so 8x does not flood the page),
  // and every 250 ms regardless, so a page that connects while paused gets one.
  constexpr auto kMinFrameGap = 22ms;
  constexpr auto kHeartbeat = 250ms;
  constexpr auto kStepBudget = 40ms;  // stepping per loop turn before the page hears from us again
  TimePoint last_frame{};
  std::uint64_t framed_tick = ~0ull;
  bool dirty = true;
  TimePoint next_status = Clock::now() + 10s;

  auto fields = [&](bool seeking) {
    return control.json_fields(player->tick(), seeking) + fmt::format(R"(,"hash_ok":{})", player->last_hash_matched());
  };
  auto check_hash = [&] {
    if (warned_hash || player->last_hash_matched()) return;
    warned_hash = true;
    fmt::print(stderr, "throng-view: tick {} re-simulates to a different state hash than the log recorded: "
               "this build diverges from the one that played it; positions from here on may differ\n", player->tick());
  };

  while (!stop.load()) {
    const TimePoint now0 = Clock::now();
    // Wake for the next tick due at this speed, a page command, or at least every 50 ms.
    const auto tick_period = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(1.0 / (hz * control.speed())));
    const TimePoint wake_at = now0 + (control.playing() ? std::clamp<Clock::duration>(tick_period, 2ms, 50ms) : Clock::duration(50ms));
    const auto got = commands.take(wake_at, errors);
    TimePoint now = Clock::now();
    for (const auto& c : got) {
      if (c.kind == LogCommand::Kind::focus) {
        focus = c.id;
      } else if (c.kind == LogCommand::Kind::contacts) {
        contacts = c.on ? std::optional<ContactsView>(ContactsView{c.camera_x, c.camera_y}) : std::nullopt;
      } else {
        control.apply(c, now);
      }
      dirty = true;
    }

    if (const auto seek = control.take_seek()) {
      web->broadcast(timeline_json(fields(true)));  // the page shows "seeking…" while we block
      const auto r = player->seek(*seek);
      check_hash();
      if (!o.quiet && r.ms > 500)
        fmt::print(stderr, "throng-view: seek to tick {} took {:.1f} s ({} ticks re-simulated)\n", r.tick, r.ms / 1000.0,
                   r.ticks_simulated);
      now = Clock::now();
      control.advance(now);  // the seek's own duration is not play time
      control.reached(player->tick());
      dirty = true;
    }

    const std::uint64_t target = control.advance(now);
    if (target < player->tick()) {  // cannot happen without a seek; stay correct anyway
      player->seek(target);
    }
    const TimePoint step_until = now + kStepBudget;
    while (player->tick() < target && Clock::now() < step_until) {
      if (!player->step()) break;
      check_hash();
    }
    control.reached(player->tick());

    now = Clock::now();
    const bool new_tick = player->tick() != framed_tick;
    if (((new_tick || dirty) && now - last_frame >= kMinFrameGap) || now - last_frame >= kHeartbeat) {
      std::uint64_t errors_total = 0;
      for (auto e : errors) errors_total += e;
      web->broadcast(frames.frame_json(player->match(), fields(false), focus, web->sessions(), errors_total, contacts));
      framed_tick = player->tick();
      last_frame = now;
      dirty = false;
    }

    report_rejections(errors, reported);
    if (!o.quiet && now >= next_status) {
      next_status = now + 10s;
      fmt::print(stderr, "throng-view: replay tick {}/{} ({} / {})  {}  {:g}x  pages {}\n", player->tick(), last,
                 mmss(static_cast<double>(player->tick()) / hz), mmss(static_cast<double>(last) / hz),
                 control.playing() ? "playing" : "paused", control.speed(), web->sessions());
    }
  }
  web->stop();
  return 0;
}

}  // namespace throng::view
