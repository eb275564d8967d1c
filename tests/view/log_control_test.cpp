// Log mode's page messages and play state machine (log_control.h), with an injected clock.
#include <gtest/gtest.h>

#include <limits>

#include <nlohmann/json.hpp>

#include "throng/view/log_control.h"

namespace throng::view {
namespace {

using namespace std::chrono_literals;
using TP = LogController::TimePoint;
const TP t0{std::chrono::seconds(1000)};

LogCommand cmd(std::string_view text) {
  auto r = parse_log_message(text);
  EXPECT_TRUE(std::holds_alternative<LogCommand>(r)) << text << " -> " << to_string(std::get<InputError>(r));
  return std::holds_alternative<LogCommand>(r) ? std::get<LogCommand>(r) : LogCommand{};
}

InputError err(std::string_view text) {
  auto r = parse_log_message(text);
  EXPECT_TRUE(std::holds_alternative<InputError>(r)) << text << " was accepted";
  return std::holds_alternative<InputError>(r) ? std::get<InputError>(r) : InputError::count_;
}

TEST(LogMessages, AcceptsTheCommands) {
  EXPECT_EQ(cmd(R"({"type":"play"})").kind, LogCommand::Kind::play);
  EXPECT_EQ(cmd(R"({"type":"pause"})").kind, LogCommand::Kind::pause);
  EXPECT_EQ(cmd(R"({"type":"toggle","extra":[1]})").kind, LogCommand::Kind::toggle);
  const auto s = cmd(R"({"type":"speed","speed":0.25})");
  EXPECT_EQ(s.kind, LogCommand::Kind::speed);
  EXPECT_EQ(s.speed, 0.25);
  EXPECT_EQ(cmd(R"({"type":"speed","speed":8})").speed, 8.0);
  const auto k = cmd(R"({"type":"seek","tick":123.4})");
  EXPECT_EQ(k.kind, LogCommand::Kind::seek);
  EXPECT_DOUBLE_EQ(k.tick, 123.4);
  EXPECT_EQ(cmd(R"({"type":"seek","tick":-5})").tick, -5.0);  // clamped by the controller, not refused
  const auto f = cmd(R"({"type":"focus","id":4194305})");
  EXPECT_EQ(f.kind, LogCommand::Kind::focus);
  EXPECT_EQ(f.id, 4194305u);
  EXPECT_EQ(cmd(R"({"type":"focus","id":0})").id, 0u);
  const auto on = cmd(R"({"type":"contacts","on":true,"camera_x":-12.5,"camera_y":3})");
  EXPECT_EQ(on.kind, LogCommand::Kind::contacts);
  EXPECT_TRUE(on.on);
  EXPECT_EQ(on.camera_x, -12.5);
  EXPECT_EQ(on.camera_y, 3.0);
  const auto off = cmd(R"({"type":"contacts","on":false})");
  EXPECT_EQ(off.kind, LogCommand::Kind::contacts);
  EXPECT_FALSE(off.on);
}

TEST(LogMessages, RejectsBadMessages) {
  EXPECT_EQ(err("seek 10"), InputError::not_json);
  EXPECT_EQ(err(R"({"type":"seek","tick":NaN})"), InputError::not_json);  // JSON has no NaN literal
  EXPECT_EQ(err(R"({"type":"seek","tick":Infinity})"), InputError::not_json);
  EXPECT_EQ(err(R"({"type":"seek","tick":1e400})"), InputError::not_json);  // overflows a double
  EXPECT_EQ(err(R"({"type":"seek","tick":"NaN"})"), InputError::bad_type);
  EXPECT_EQ(err(R"({"type":"seek","tick":null})"), InputError::bad_type);
  EXPECT_EQ(err(R"({"type":"seek"})"), InputError::bad_type);
  EXPECT_EQ(err(R"({"type":"speed","speed":0.1})"), InputError::out_of_range);
  EXPECT_EQ(err(R"({"type":"speed","speed":16})"), InputError::out_of_range);
  EXPECT_EQ(err(R"({"type":"speed","speed":-1})"), InputError::out_of_range);
  EXPECT_EQ(err(R"({"type":"speed","speed":"2"})"), InputError::bad_type);
  EXPECT_EQ(err(R"({"type":"focus","id":-3})"), InputError::out_of_range);
  EXPECT_EQ(err(R"({"type":"focus","id":1.5})"), InputError::out_of_range);
  EXPECT_EQ(err(R"({"type":"focus","id":4294967296})"), InputError::out_of_range);
  EXPECT_EQ(err(R"({"type":"focus"})"), InputError::bad_type);
  EXPECT_EQ(err(R"({"type":"contacts"})"), InputError::bad_type);
  EXPECT_EQ(err(R"({"type":"contacts","on":1,"camera_x":0,"camera_y":0})"), InputError::bad_type);
  EXPECT_EQ(err(R"({"type":"contacts","on":true})"), InputError::bad_type);  // the camera is required
  EXPECT_EQ(err(R"({"type":"contacts","on":true,"camera_x":0,"camera_y":"0"})"), InputError::bad_type);
  EXPECT_EQ(err(R"({"type":"contacts","on":true,"camera_x":0,"camera_y":2e4})"), InputError::out_of_range);
  EXPECT_EQ(err(R"({"type":"rewind"})"), InputError::unknown_type);
  EXPECT_EQ(err(R"({"type":"input","move_x":1})"), InputError::unknown_type);  // nothing to control in a replay
  EXPECT_EQ(err(R"({"tick":3})"), InputError::unknown_type);
  EXPECT_EQ(err(R"({"type":7})"), InputError::unknown_type);
  EXPECT_EQ(err(R"([1,2])"), InputError::not_object);
  EXPECT_EQ(err(std::string(kMaxPageMessageBytes + 1, ' ')), InputError::too_large);
}

TEST(LogController, PlaysAtTickRateTimesSpeedAndStopsAtTheEnd) {
  LogController c({600, 30}, 0, 1.0, true, t0);
  EXPECT_EQ(c.advance(t0), 0u);
  EXPECT_EQ(c.advance(t0 + 1s), 30u);
  c.apply(cmd(R"({"type":"speed","speed":4})"), t0 + 1s);
  EXPECT_EQ(c.advance(t0 + 2s), 150u);  // 30 + 4 * 30
  c.apply(cmd(R"({"type":"speed","speed":0.25})"), t0 + 2s);
  EXPECT_EQ(c.advance(t0 + 6s), 180u);  // + 0.25 * 30 * 4
  EXPECT_TRUE(c.playing());
  c.apply(cmd(R"({"type":"speed","speed":8})"), t0 + 6s);
  EXPECT_EQ(c.advance(t0 + 60s), 600u);  // clamped at the last tick
  EXPECT_FALSE(c.playing()) << "stops at the end (no loop)";
  EXPECT_TRUE(c.at_end());
  EXPECT_EQ(c.advance(t0 + 70s), 600u);
  // Play at the end starts over from tick 0 (a seek the loop performs).
  c.apply(cmd(R"({"type":"play"})"), t0 + 70s);
  EXPECT_TRUE(c.playing());
  EXPECT_EQ(c.take_seek(), std::optional<std::uint64_t>(0));
  EXPECT_EQ(c.advance(t0 + 71s), 240u);  // 8x
}

TEST(LogController, PauseHoldsTheTickAndToggleResumes) {
  LogController c({600, 30}, 10, 1.0, true, t0);
  EXPECT_EQ(c.advance(t0 + 1s), 40u);
  c.apply(cmd(R"({"type":"pause"})"), t0 + 1s);
  EXPECT_FALSE(c.playing());
  EXPECT_EQ(c.advance(t0 + 5s), 40u);
  EXPECT_EQ(c.advance(t0 + 50s), 40u);
  c.apply(cmd(R"({"type":"toggle"})"), t0 + 50s);  // paused time is not played
  EXPECT_TRUE(c.playing());
  EXPECT_EQ(c.advance(t0 + 51s), 70u);
  c.apply(cmd(R"({"type":"toggle"})"), t0 + 51s);
  EXPECT_FALSE(c.playing());
  c.apply(cmd(R"({"type":"pause"})"), t0 + 52s);  // pausing twice is harmless
  EXPECT_EQ(c.advance(t0 + 53s), 70u);
  EXPECT_FALSE(c.take_seek());
}

TEST(LogController, SeeksAreClampedRoundedAndCoalesced) {
  LogController c({600, 30}, 0, 1.0, false, t0);
  c.apply(cmd(R"({"type":"seek","tick":100.6})"), t0);
  EXPECT_EQ(c.target(), 101u);
  c.apply(cmd(R"({"type":"seek","tick":-40})"), t0);
  EXPECT_EQ(c.target(), 0u);
  c.apply(cmd(R"({"type":"seek","tick":1e300})"), t0);
  EXPECT_EQ(c.target(), 600u);
  c.apply(cmd(R"({"type":"seek","tick":250})"), t0);
  EXPECT_EQ(c.take_seek(), std::optional<std::uint64_t>(250)) << "only the newest seek of a drag is taken";
  EXPECT_FALSE(c.take_seek());
  EXPECT_EQ(c.advance(t0 + 10s), 250u) << "paused: a seek does not start playback";
  // A seek while playing keeps playing from there.
  c.apply(cmd(R"({"type":"play"})"), t0 + 10s);
  c.apply(cmd(R"({"type":"seek","tick":300})"), t0 + 11s);
  EXPECT_EQ(c.advance(t0 + 12s), 330u);
  // A seek to the end stops.
  c.apply(cmd(R"({"type":"seek","tick":600})"), t0 + 12s);
  EXPECT_FALSE(c.playing());
}

TEST(LogController, StartIsClampedAndAnEmptyLogNeverPlays) {
  LogController c({100, 30}, 500, 100.0, true, t0);
  EXPECT_EQ(c.target(), 100u);
  EXPECT_EQ(c.speed(), kMaxSpeed);
  EXPECT_FALSE(c.playing());
  LogController empty({0, 30}, 0, 1.0, true, t0);
  empty.apply(cmd(R"({"type":"play"})"), t0);
  EXPECT_FALSE(empty.playing());
  EXPECT_EQ(empty.advance(t0 + 5s), 0u);
  // A speed that skipped the parser is still kept in range.
  LogCommand nan_speed{LogCommand::Kind::speed, std::numeric_limits<double>::quiet_NaN()};
  c.apply(nan_speed, t0);
  EXPECT_EQ(c.speed(), kMaxSpeed);
  LogCommand nan_seek{LogCommand::Kind::seek, 1.0, std::numeric_limits<double>::quiet_NaN()};
  c.apply(nan_seek, t0);
  EXPECT_EQ(c.target(), 0u);
}

TEST(LogController, ASlowPlayerHoldsPlaybackBackInsteadOfPilingUpABacklog) {
  LogController c({100000, 30}, 0, 1.0, true, t0, /*max_lag_s=*/0.5);
  EXPECT_EQ(c.advance(t0 + 10s), 300u);
  c.reached(20);  // the player only got to 20
  EXPECT_EQ(c.target(), 35u);  // 20 + 0.5 s * 30 Hz
  EXPECT_EQ(c.advance(t0 + 11s), 65u);
  c.reached(65);
  EXPECT_EQ(c.target(), 65u);
}

TEST(LogController, TimelineFieldsAreJson) {
  LogController c({90, 30}, 45, 2.0, false, t0);
  std::string text = "{";  // built in steps: GCC 12 warns (-Wrestrict) on "{" + s + "}"
  text += c.json_fields(45, true);
  text += '}';
  const auto j = nlohmann::json::parse(text);
  EXPECT_EQ(j["tick"], 45);
  EXPECT_EQ(j["last_tick"], 90);
  EXPECT_EQ(j["tick_hz"], 30);
  EXPECT_EQ(j["playing"], false);
  EXPECT_EQ(j["speed"], 2.0);
  EXPECT_EQ(j["seeking"], true);
  EXPECT_EQ(j["at_end"], false);
}

}  // namespace
}  // namespace throng::view
