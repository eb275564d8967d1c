// Log mode frames: every body of the re-simulated world, at its position, in id order, with the
// timeline and the focused character's parameters; the match message says "replay".
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include <nlohmann/json.hpp>

#include "log_fixture.h"
#include "test_support.h"
#include "throng/matchlog/log_player.h"
#include "throng/view/log_frame.h"
#include "throng/view/match_json.h"
#include "throng/world/world.h"

namespace throng::view {
namespace {

using namespace testing;

TEST(LogFrame, CarriesEveryBodyOfTheReplayedWorldAtItsPosition) {
  TempDir dir;
  const auto path = dir / "match.tlog";
  const RecordedLog rec = record_log(path, 120, 80);
  matchlog::LogPlayer player(path.string());
  ASSERT_EQ(player.last_tick(), 120u);

  const auto match = nlohmann::json::parse(match_info_json(player.match().match_info(), "replay"));
  EXPECT_EQ(match["type"], "match");
  EXPECT_EQ(match["mode"], "replay");
  EXPECT_EQ(match["tick_hz"], 30);

  LogFrameBuilder frames;
  for (std::uint64_t t : {0ull, 1ull, 57ull, 120ull}) {
    player.seek(t);
    const World& w = player.match().world();
    const std::uint32_t focus = w.id_at(0).value;
    const auto f = nlohmann::json::parse(frames.frame_json(player.match(), R"("tick":)" + std::to_string(t), focus, 2, 5));
    EXPECT_EQ(f["type"], "frame");
    EXPECT_EQ(f["mode"], "replay");
    EXPECT_EQ(f["tick"], t);
    EXPECT_EQ(f["replay"]["tick"], t);
    EXPECT_EQ(f["pages"], 2);
    EXPECT_EQ(f["input_errors_total"], 5);
    const auto& o = f["objects"];
    ASSERT_EQ(o.size(), 4 * w.body_count());
    EXPECT_EQ(f["in_view"], w.body_count());
    std::uint32_t previous = 0;
    for (std::size_t i = 0; i < o.size(); i += 4) {
      const std::uint32_t id = o[i].get<std::uint32_t>();
      EXPECT_GT(id, previous) << "ids ascending";
      previous = id;
      const Vec3 p = w.position(ObjectId{id});
      EXPECT_NEAR(o[i + 1].get<double>(), p.x, 0.0006) << "tick " << t << " id " << id;
      EXPECT_NEAR(o[i + 2].get<double>(), p.y, 0.0006) << "tick " << t << " id " << id;
      EXPECT_LE(std::abs(o[i + 3].get<double>()), 3.15);
    }
    ASSERT_TRUE(f["focus"].is_object());
    EXPECT_EQ(f["focus"]["id"], focus);
    EXPECT_GT(f["focus"]["weight_kg"].get<double>(), 0.0);
    frames.reset_yaw();
  }
  EXPECT_EQ(rec.bodies, player.match().world().body_count());

  // No focus, or one that is not a body: null.
  const auto none = nlohmann::json::parse(frames.frame_json(player.match(), R"("tick":0)", 0, 0, 0));
  EXPECT_TRUE(none["focus"].is_null());
  const auto gone = nlohmann::json::parse(frames.frame_json(player.match(), R"("tick":0)", 0xFFFFFFu, 0, 0));
  EXPECT_TRUE(gone["focus"].is_null());

  const auto timeline = nlohmann::json::parse(timeline_json(R"("tick":3,"seeking":true)"));
  EXPECT_EQ(timeline["type"], "timeline");
  EXPECT_EQ(timeline["seeking"], true);
}

TEST(LogFrame, YawFollowsTheDirectionOfTravel) {
  TempDir dir;
  const auto path = dir / "match.tlog";
  record_log(path, 90, 60);
  matchlog::LogPlayer player(path.string());
  LogFrameBuilder frames;
  player.seek(60);
  frames.frame_json(player.match(), R"("tick":60)", 0, 0, 0);
  player.step();
  const World& w = player.match().world();
  const auto f = nlohmann::json::parse(frames.frame_json(player.match(), R"("tick":61)", 0, 0, 0));
  int moving = 0;
  for (std::size_t i = 0; i < f["objects"].size(); i += 4) {
    const Vec3 v = w.velocity(ObjectId{f["objects"][i].get<std::uint32_t>()});
    if (v.x * v.x + v.y * v.y < 0.01) continue;
    ++moving;
    EXPECT_NEAR(f["objects"][i + 3].get<double>(), std::atan2(v.y, v.x), 0.006);
  }
  EXPECT_GT(moving, 0) << "nobody moves in the recorded battle";
}

}  // namespace
}  // namespace throng::view
