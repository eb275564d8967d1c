#pragma once
// Log mode (throng-view --log): what the page may send, and the play/pause/speed/seek state machine
// that turns wall time into the tick the re-simulated match should show. Transport-free and
// clock-injected, so it is unit-tested without a log, a browser or sleeping.
//
// Page -> viewer messages in log mode (JSON text, at most kMaxPageMessageBytes; checked on the
// web thread like live input, errors are the same InputError reasons):
//   {"type":"play"}  {"type":"pause"}  {"type":"toggle"}
//   {"type":"speed","speed":x}   x a finite number in [kMinSpeed, kMaxSpeed], else out_of_range
//   {"type":"seek","tick":t}     t a finite number (JSON has no NaN; a string is bad_type);
//                                rounded, then clamped to [0, last tick] by the controller
//   {"type":"focus","id":n}      the character the page follows (0 = none): frames carry its
//                                parameters; n an integer in [0, 2^32), else out_of_range
//   {"type":"contacts","on":b,"camera_x":x,"camera_y":y}
//                                the contacts overlay: b a boolean (else bad_type); while on,
//                                frames carry the contact pairs nearest (x, y), which are
//                                required then: finite numbers within +-kMaxCameraM (else
//                                bad_type / out_of_range)
// Anything else ("input" included: there is nothing to control in a replay) is unknown_type.
//
// Playing advances a fractional position by elapsed * tick_hz * speed. At the last tick playback
// stops (paused, at_end); play from there starts again at tick 0. When re-simulation is slower
// than the requested speed, reached() holds the position at most max_lag_s of play time ahead of
// the player, so playback slows down instead of piling up a backlog to catch up on.
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "throng/view/page_input.h"

namespace throng::view {

inline constexpr double kMinSpeed = 0.25;
inline constexpr double kMaxSpeed = 8.0;

struct LogCommand {
  enum class Kind : std::uint8_t { play, pause, toggle, speed, seek, focus, contacts } kind = Kind::play;
  double speed = 1.0;    // speed
  double tick = 0.0;     // seek: the page's target, not yet clamped
  std::uint32_t id = 0;  // focus (the controller ignores it: the viewer loop keeps it)
  bool on = false;       // contacts (the viewer loop keeps it, like focus)
  double camera_x = 0.0, camera_y = 0.0;
};

std::variant<LogCommand, InputError> parse_log_message(std::string_view text);

struct LogTimeline {
  std::uint64_t last_tick = 0;  // ticks 0 (before the first) .. last_tick can be shown
  std::uint32_t tick_hz = 30;
};

class LogController {
 public:
  using Clock = std::chrono::steady_clock;
  using TimePoint = Clock::time_point;

  // start_tick is clamped like a seek; speed must be within [kMinSpeed, kMaxSpeed] (clamped).
  LogController(LogTimeline timeline, std::uint64_t start_tick, double speed, bool playing, TimePoint now,
                double max_lag_s = 0.5);

  void apply(const LogCommand& command, TimePoint now);
  // Moves the play position to `now` and returns the tick the player should be at.
  std::uint64_t advance(TimePoint now);
  // The player is at `tick` (after stepping towards advance()'s target).
  void reached(std::uint64_t tick);
  // The newest explicit seek not yet taken (a drag sends many: only the last one matters).
  std::optional<std::uint64_t> take_seek();

  bool playing() const { return playing_; }
  double speed() const { return speed_; }
  bool at_end() const { return target() >= timeline_.last_tick; }
  std::uint64_t target() const { return static_cast<std::uint64_t>(position_); }
  const LogTimeline& timeline() const { return timeline_; }

  // "timeline" fields for the page: tick (shown), last_tick, tick_hz, playing, speed, seeking, at_end.
  std::string json_fields(std::uint64_t shown_tick, bool seeking) const;

 private:
  std::uint64_t clamp_tick(double tick) const;

  LogTimeline timeline_;
  double position_ = 0.0;  // in ticks; the integer part is the target tick
  double speed_ = 1.0;
  bool playing_ = false;
  TimePoint last_;
  double max_lag_s_;
  std::optional<std::uint64_t> pending_seek_;
};

}  // namespace throng::view
