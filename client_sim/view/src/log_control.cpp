// Log mode: page messages and the play state machine (see log_control.h).
#include "throng/view/log_control.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace throng::view {

namespace {

// A required number field: its value when present and finite, else the error.
std::variant<double, InputError> required_number(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  if (it == j.end() || !it->is_number()) return InputError::bad_type;
  const double v = it->get<double>();
  if (!std::isfinite(v)) return InputError::non_finite;
  return v;
}

}  // namespace

std::variant<LogCommand, InputError> parse_log_message(std::string_view text) {
  if (text.size() > kMaxPageMessageBytes) return InputError::too_large;
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return InputError::not_json;  // NaN/Infinity literals and overflowing numbers too
  if (!j.is_object()) return InputError::not_object;
  const auto type = j.find("type");
  if (type == j.end() || !type->is_string()) return InputError::unknown_type;
  const std::string& t = type->get_ref<const std::string&>();
  LogCommand c;
  if (t == "play") {
    c.kind = LogCommand::Kind::play;
  } else if (t == "pause") {
    c.kind = LogCommand::Kind::pause;
  } else if (t == "toggle") {
    c.kind = LogCommand::Kind::toggle;
  } else if (t == "speed") {
    auto v = required_number(j, "speed");
    if (auto* e = std::get_if<InputError>(&v)) return *e;
    c.kind = LogCommand::Kind::speed;
    c.speed = std::get<double>(v);
    if (c.speed < kMinSpeed || c.speed > kMaxSpeed) return InputError::out_of_range;
  } else if (t == "seek") {
    auto v = required_number(j, "tick");
    if (auto* e = std::get_if<InputError>(&v)) return *e;
    c.kind = LogCommand::Kind::seek;
    c.tick = std::get<double>(v);
  } else if (t == "focus") {
    const auto id = j.find("id");
    if (id == j.end() || !id->is_number()) return InputError::bad_type;
    if (!id->is_number_integer()) return InputError::out_of_range;  // fractional
    if (!id->is_number_unsigned() && id->get<std::int64_t>() != 0) return InputError::out_of_range;  // negative
    if (id->is_number_unsigned() && id->get<std::uint64_t>() > 0xFFFFFFFFull) return InputError::out_of_range;
    c.kind = LogCommand::Kind::focus;
    c.id = id->is_number_unsigned() ? static_cast<std::uint32_t>(id->get<std::uint64_t>()) : 0u;
  } else if (t == "contacts") {
    const auto on = j.find("on");
    if (on == j.end() || !on->is_boolean()) return InputError::bad_type;
    c.kind = LogCommand::Kind::contacts;
    c.on = on->get<bool>();
    if (c.on) {
      auto x = required_number(j, "camera_x");
      if (auto* e = std::get_if<InputError>(&x)) return *e;
      auto y = required_number(j, "camera_y");
      if (auto* e = std::get_if<InputError>(&y)) return *e;
      c.camera_x = std::get<double>(x);
      c.camera_y = std::get<double>(y);
      if (std::abs(c.camera_x) > kMaxCameraM || std::abs(c.camera_y) > kMaxCameraM) return InputError::out_of_range;
    }
  } else {
    return InputError::unknown_type;
  }
  return c;
}

LogController::LogController(LogTimeline timeline, std::uint64_t start_tick, double speed, bool playing, TimePoint now,
                             double max_lag_s)
    : timeline_(timeline),
      speed_(std::clamp(speed, kMinSpeed, kMaxSpeed)),
      playing_(playing),
      last_(now),
      max_lag_s_(max_lag_s) {
  if (timeline_.tick_hz == 0) timeline_.tick_hz = 1;  // a header the reader accepted never has 0; stay finite anyway
  position_ = static_cast<double>(clamp_tick(static_cast<double>(start_tick)));
  if (at_end()) playing_ = false;
}

std::uint64_t LogController::clamp_tick(double tick) const {
  if (!(tick > 0.0)) return 0;  // negative (and NaN, should one ever get here)
  const double r = std::round(tick);
  if (r >= static_cast<double>(timeline_.last_tick)) return timeline_.last_tick;
  return static_cast<std::uint64_t>(r);
}

void LogController::apply(const LogCommand& c, TimePoint now) {
  advance(now);  // time played so far counts at the old speed / state
  switch (c.kind) {
    case LogCommand::Kind::play:
      if (at_end()) {  // play at the end starts over, as video players do
        position_ = 0.0;
        pending_seek_ = 0;
      }
      playing_ = timeline_.last_tick > 0;
      break;
    case LogCommand::Kind::pause:
      playing_ = false;
      break;
    case LogCommand::Kind::toggle:
      if (playing_) {
        playing_ = false;
      } else {
        apply(LogCommand{LogCommand::Kind::play}, now);
      }
      break;
    case LogCommand::Kind::speed:
      // The parser rejects out-of-range speeds; a caller that skipped it still gets a valid one.
      if (std::isfinite(c.speed)) speed_ = std::clamp(c.speed, kMinSpeed, kMaxSpeed);
      break;
    case LogCommand::Kind::focus:
    case LogCommand::Kind::contacts:
      break;
    case LogCommand::Kind::seek: {
      const std::uint64_t t = clamp_tick(c.tick);
      position_ = static_cast<double>(t);
      pending_seek_ = t;
      if (at_end()) playing_ = false;
      break;
    }
  }
  last_ = now;
}

std::uint64_t LogController::advance(TimePoint now) {
  if (now > last_ && playing_) {
    const double dt = std::chrono::duration<double>(now - last_).count();
    position_ += dt * timeline_.tick_hz * speed_;
    if (position_ >= static_cast<double>(timeline_.last_tick)) {
      position_ = static_cast<double>(timeline_.last_tick);
      playing_ = false;  // stop at the end (no loop)
    }
  }
  if (now > last_) last_ = now;
  return target();
}

void LogController::reached(std::uint64_t tick) {
  const double max_ahead = std::max(1.0, max_lag_s_ * timeline_.tick_hz * speed_);
  const double limit = static_cast<double>(tick) + max_ahead;
  if (position_ > limit) position_ = limit;
}

std::optional<std::uint64_t> LogController::take_seek() {
  auto s = pending_seek_;
  pending_seek_.reset();
  return s;
}

std::string LogController::json_fields(std::uint64_t shown_tick, bool seeking) const {
  return fmt::format(R"("tick":{},"target":{},"last_tick":{},"tick_hz":{},"playing":{},"speed":{},"seeking":{},"at_end":{})",
                     shown_tick, target(), timeline_.last_tick, timeline_.tick_hz, playing_, speed_, seeking,
                     shown_tick >= timeline_.last_tick);
}

}  // namespace throng::view
