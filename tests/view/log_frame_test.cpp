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

TEST(LogFrame, YawIsTheMatchsFacing) {
  TempDir dir;
  const auto path = dir / "match.tlog";
  record_log(path, 90, 60);
  matchlog::LogPlayer player(path.string());
  LogFrameBuilder frames;
  player.seek(61);
  const auto f = nlohmann::json::parse(frames.frame_json(player.match(), R"("tick":61)", 0, 0, 0));
  int turned = 0;
  for (std::size_t i = 0; i < f["objects"].size(); i += 4) {
    const auto yaw = player.match().facing_rad(ObjectId{f["objects"][i].get<std::uint32_t>()});
    ASSERT_TRUE(yaw.has_value());
    EXPECT_NEAR(f["objects"][i + 3].get<double>(), *yaw, 0.006);  // printed to 0.01 rad
    if (std::abs(*yaw) > 0.01) ++turned;
  }
  EXPECT_GT(turned, 0) << "nobody turned in the recorded battle: the test proves nothing";
}

// The contacts overlay in log mode: the pairs nearest the page's camera, the same the live server
// would send (ContactSelector over the re-simulated world's push events, ContactsConfig defaults).
TEST(LogFrame, ContactsAreThePairsNearTheCameraWithTheWorldsShares) {
  TempDir dir;
  const auto path = dir / "match.tlog";
  const RecordedLog rec = record_log(path, 120, 80);
  matchlog::PlayerOptions po;
  po.resim.exact_interest = false;
  po.resim.record_push_events = true;  // what throng-view --log sets
  matchlog::LogPlayer player(path.string(), po);
  LogFrameBuilder frames;
  std::size_t pairs_seen = 0;
  for (std::uint64_t t : {30ull, 90ull, 120ull}) {
    player.seek(t);
    const World& w = player.match().world();
    // Camera on the first body-body contact of the tick, so there is something near it.
    double cx = 0, cy = 0;
    for (const PushEvent& e : w.push_events())
      if (w.is_body(e.a) && w.is_body(e.b)) {
        cx = w.position(e.a).x;
        cy = w.position(e.a).y;
        break;
      }
    const auto off = nlohmann::json::parse(frames.frame_json(player.match(), R"("tick":0)", 0, 0, 0));
    EXPECT_TRUE(off["contacts"].is_null()) << "no overlay asked for";
    const auto f = nlohmann::json::parse(frames.frame_json(player.match(), R"("tick":0)", 0, 0, 0, ContactsView{cx, cy}));
    ASSERT_TRUE(f["contacts"].is_object()) << "tick " << t;
    const auto& c = f["contacts"];
    EXPECT_EQ(c["tick"], t);
    std::map<std::pair<std::uint32_t, std::uint32_t>, float> share;
    std::size_t near = 0;
    const match::ContactsConfig cfg{};
    for (const PushEvent& e : w.push_events()) {
      if (!w.is_body(e.a) || !w.is_body(e.b)) continue;
      share[{e.a.value, e.b.value}] = e.share_a;
      const Vec3 a = w.position(e.a), b = w.position(e.b);
      if (std::hypot((a.x + b.x) / 2 - cx, (a.y + b.y) / 2 - cy) <= cfg.radius_m) ++near;
    }
    EXPECT_EQ(c["near"], near);
    const auto& p = c["pairs"];
    ASSERT_EQ(p.size() % 5, 0u);
    EXPECT_EQ(p.size() / 5, std::min<std::size_t>(near, cfg.max_pairs));
    for (std::size_t i = 0; i < p.size(); i += 5) {
      const auto it = share.find({p[i].get<std::uint32_t>(), p[i + 1].get<std::uint32_t>()});
      ASSERT_NE(it, share.end()) << "a pair the world did not push";
      EXPECT_NEAR(p[i + 2].get<double>(), it->second, 1e-4);
      EXPECT_GT(p[i + 2].get<double>(), 0.0);
      EXPECT_LT(p[i + 2].get<double>(), 1.0);
    }
    pairs_seen += p.size() / 5;
  }
  EXPECT_GT(pairs_seen, 0u) << "no contacts in the recorded battle: the test proves nothing";
  EXPECT_GT(rec.bodies, 0u);
}

}  // namespace
}  // namespace throng::view
