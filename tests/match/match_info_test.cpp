#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "match_test_util.h"
#include "throng/match/match.h"
#include "throng/match/match_config.h"
#include "throng/params/categories.h"
#include "throng/world/world.h"

namespace throng::match {
namespace {

TEST(MatchInfo, DescribesTheSceneAndTheRoster) {
  MatchConfig config = test::small_config();
  config.max_clients = 17;
  config.interest.radius_m = 25.0;
  Match m(test::two_armies(20), config, "match-42");
  const protocol::MatchInfo& info = m.match_info();
  EXPECT_EQ(info.protocol_version, protocol::kProtocolVersion);
  EXPECT_EQ(info.match_id, "match-42");
  EXPECT_EQ(info.scene_name, "two_armies");
  EXPECT_EQ(info.tick_hz, 30u);
  EXPECT_EQ(info.max_clients, 17u);
  EXPECT_FLOAT_EQ(info.interest_radius_m, 25.0f);
  EXPECT_EQ(info.state, protocol::MatchState::running);
  EXPECT_EQ(info.param_version, 0u);
  EXPECT_NE(info.param_table_hash, 0u);
  EXPECT_NE(info.push_policy_hash, 0u);
  // Built-in table archetypes, sorted.
  EXPECT_TRUE(std::is_sorted(info.archetypes.begin(), info.archetypes.end()));
  const auto infantry = std::find(info.archetypes.begin(), info.archetypes.end(), "infantry");
  ASSERT_NE(infantry, info.archetypes.end());

  ASSERT_EQ(info.scenery.size(), 2u);
  const protocol::SceneryShape& wall = info.scenery[0];
  EXPECT_EQ(wall.kind, protocol::ShapeKind::box);
  EXPECT_EQ(wall.archetype, "wall");
  EXPECT_TRUE(m.world().is_fixed(ObjectId{wall.id}));
  EXPECT_FLOAT_EQ(wall.cy, 30.0f);
  EXPECT_FLOAT_EQ(wall.hx, 5.0f);
  EXPECT_NEAR(wall.yaw_rad, 30.0 * std::numbers::pi / 180.0, 1e-6);
  EXPECT_FLOAT_EQ(wall.softness, 0.0f);
  const protocol::SceneryShape& bush = info.scenery[1];
  EXPECT_EQ(bush.kind, protocol::ShapeKind::cylinder);
  EXPECT_EQ(bush.archetype, "bush");
  EXPECT_FLOAT_EQ(bush.radius, 1.5f);
  EXPECT_FLOAT_EQ(bush.half_height, 0.6f);
  EXPECT_FLOAT_EQ(bush.softness, 0.6f);

  const protocol::Roster& r = info.roster;
  const World& w = m.world();
  ASSERT_EQ(r.id.size(), w.body_count());
  ASSERT_EQ(r.radius_mm.size(), w.body_count());
  ASSERT_EQ(r.half_height_mm.size(), w.body_count());
  ASSERT_EQ(r.faction.size(), w.body_count());
  ASSERT_EQ(r.character_type.size(), w.body_count());
  ASSERT_EQ(r.archetype.size(), w.body_count());
  int per_faction[3] = {0, 0, 0};
  for (std::size_t i = 0; i < r.id.size(); ++i) {
    EXPECT_TRUE(w.is_body(ObjectId{r.id[i]}));
    EXPECT_EQ(r.radius_mm[i], 350);
    EXPECT_EQ(r.half_height_mm[i], 0);
    EXPECT_EQ(r.character_type[i], static_cast<std::uint8_t>(params::CharacterType::npc));
    EXPECT_EQ(info.archetypes.at(r.archetype[i]), "infantry");
    ++per_faction[r.faction[i]];
  }
  EXPECT_EQ(per_faction[1], 20);
  EXPECT_EQ(per_faction[2], 20);

  // Bounds: bodies within +-20 m in x (gap 30, half 5), wall up to y ~ 32.5, bush to -31.5,
  // plus the 10 m margin.
  double min_x = 1e9, max_x = -1e9;
  for (std::size_t d = 0; d < w.body_count(); ++d) {
    min_x = std::min(min_x, w.pos_x()[d] - 0.35);
    max_x = std::max(max_x, w.pos_x()[d] + 0.35);
  }
  EXPECT_NEAR(info.world_min_x, min_x - 10.0, 1e-4);
  EXPECT_NEAR(info.world_max_x, max_x + 10.0, 1e-4);
  EXPECT_NEAR(info.world_min_y, -31.5 - 10.0, 1e-4);
  const double wall_y = 30.0 + 5.0 * std::sin(std::numbers::pi / 6) + 0.4 * std::cos(std::numbers::pi / 6);
  EXPECT_NEAR(info.world_max_y, wall_y + 10.0, 1e-4);
}

TEST(MatchInfo, RepublishedOnFirstTickAndAtShutdown) {
  Match m(test::two_armies(), test::small_config(), "m");
  Outbox out;
  m.tick(out);
  EXPECT_TRUE(out.match_info_changed);
  m.tick(out);
  EXPECT_FALSE(out.match_info_changed);
  m.begin_shutdown();
  EXPECT_EQ(m.match_info().state, protocol::MatchState::ended);
  m.tick(out);
  EXPECT_TRUE(out.match_info_changed);
  m.begin_shutdown();  // idempotent
  m.tick(out);
  EXPECT_FALSE(out.match_info_changed);
}

TEST(MatchInfo, TickRateDrivesTheWorld) {
  MatchConfig config = test::small_config();
  config.tick_hz = 20;
  Match m(test::two_armies(), config, "m");
  EXPECT_DOUBLE_EQ(m.world().settings().dt_s, 1.0 / 20.0);
  EXPECT_EQ(m.config().tick_hz, 20u);
}

TEST(MatchConfig, ValidationNamesTheField) {
  const auto expect_bad = [](MatchConfig c, const char* field) {
    try {
      validate_config(c);
      ADD_FAILURE() << "accepted a bad " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  validate_config(MatchConfig{});
  MatchConfig c;
  c.tick_hz = 0;
  expect_bad(c, "tick_hz");
  c = {};
  c.client_timeout_s = std::nan("");
  expect_bad(c, "client_timeout_s");
  c = {};
  c.client_timeout_s = 0.001;  // shorter than a tick
  expect_bad(c, "client_timeout_s");
  c = {};
  c.max_commands_per_tick = 0;
  expect_bad(c, "max_commands_per_tick");
  c = {};
  c.camera_limit_m = 2e6;  // beyond what snapshots serve: an accepted camera would fail the tick
  expect_bad(c, "camera_limit_m");
  c = {};
  c.player_speed_mps = -1;
  expect_bad(c, "player_speed_mps");
  c = {};
  c.interest.exit_hysteresis = 0.5;
  expect_bad(c, "interest.exit_hysteresis");
  c = {};
  c.max_clients = 0;
  expect_bad(c, "max_clients");
  // The match refuses to start with it.
  EXPECT_THROW(Match(test::two_armies(), c, "m"), std::invalid_argument);
}

}  // namespace
}  // namespace throng::match
