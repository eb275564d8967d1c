#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>
#include <vector>

#include "throng/client_sim/behavior.h"
#include "throng/protocol/codec.h"

namespace throng::client_sim {
namespace {

// A sink like the bot's: prefills and numbers the commands.
class TestSink final : public CommandSink {
 public:
  protocol::Command& emit(const Intent& i, Expect e) override {
    protocol::Command c;
    c.client_id = 1;
    c.entity = 10;
    c.sequence = next_++;
    c.move_x = i.move_x;
    c.move_y = i.move_y;
    c.facing_rad = i.facing_rad;
    c.actions = i.actions;
    commands.push_back(c);
    expects.push_back(e);
    return commands.back();
  }
  std::vector<protocol::Command> commands;
  std::vector<Expect> expects;

 private:
  std::uint32_t next_ = 1;
};

struct Fixture {
  Fixture() {
    protocol::MatchInfo info;
    info.tick_hz = 30;
    info.world_min_x = -50;
    info.world_min_y = -50;
    info.world_max_x = 50;
    info.world_max_y = 50;
    info.roster.id = {10, 20, 30, 40};
    info.roster.radius_mm = {350, 350, 350, 350};
    info.roster.half_height_mm = {0, 0, 0, 0};
    info.roster.faction = {0, 0, 1, 1};
    info.roster.character_type = {0, 0, 0, 0};
    info.roster.archetype = {0, 0, 0, 0};
    world.set_match(std::make_shared<const MatchView>(info));
    protocol::Snapshot s;
    s.client_id = 1;
    s.tick = 1;
    s.entity = 10;
    const std::vector<protocol::Pose> poses{{20, 1, 0, 0, 0}, {30, 0, 8, 0, 0}, {40, -5, 0, 0, 0}};
    EXPECT_TRUE(protocol::encode_poses(poses, 0, 0, 1, s));
    EXPECT_EQ(world.apply(s), ClientWorld::ApplyResult::applied);
  }
  BehaviorContext ctx(double t, std::span<const std::uint32_t> others = {}) {
    return BehaviorContext{world, 1, 10, 0, self, spawn, t, 30, rng, others};
  }
  ClientWorld world;
  ObjectState self{10, 0, 0, 0, 0};
  ObjectState spawn{10, 0, 0, 0, 0};
  std::mt19937_64 rng{42};
};

void expect_valid(const protocol::Command& c) {
  ASSERT_TRUE(std::isfinite(c.move_x) && std::isfinite(c.move_y) && std::isfinite(c.facing_rad));
  EXPECT_LE(std::hypot(c.move_x, c.move_y), 1.0f + 1e-6f);
  EXPECT_LE(std::abs(c.facing_rad), protocol::kPi + 1e-6);
  EXPECT_EQ(c.actions & ~protocol::kKnownActions, 0u);
}

TEST(Behavior, SpecsExpand) {
  EXPECT_EQ(expand_behavior_spec("wander"), std::vector<std::string>{"wander"});
  EXPECT_EQ(expand_behavior_spec("nan,flood"), (std::vector<std::string>{"nan", "flood"}));
  EXPECT_EQ(expand_behavior_spec("mix"), (std::vector<std::string>{"wander", "charge", "waypoints", "idle"}));
  EXPECT_THROW(expand_behavior_spec("dance"), std::invalid_argument);
  EXPECT_THROW(expand_behavior_spec("wander,"), std::invalid_argument);
  EXPECT_THROW(expand_behavior_spec(""), std::invalid_argument);
  for (const auto& n : behavior_names()) EXPECT_EQ(make_behavior(n)->name(), n);
  EXPECT_TRUE(is_misbehavior("hijack"));
  EXPECT_FALSE(is_misbehavior("charge"));
}

TEST(Behavior, HonestBehavioursSendOneValidCommandPerTick) {
  for (const char* name : {"wander", "charge", "waypoints", "idle"}) {
    Fixture f;
    auto b = make_behavior(name);
    TestSink sink;
    for (int t = 0; t < 200; ++t) {
      const auto before = sink.commands.size();
      b->act(f.ctx(t / 30.0), sink);
      ASSERT_EQ(sink.commands.size(), before + 1) << name;
      expect_valid(sink.commands.back());
      EXPECT_EQ(sink.expects.back(), Expect::accept);
      // Follow the intent a little so position-dependent behaviors progress.
      f.self.x += sink.commands.back().move_x * 0.1;
      f.self.y += sink.commands.back().move_y * 0.1;
    }
  }
}

TEST(Behavior, ChargeRunsAtTheNearestEnemy) {
  Fixture f;
  auto b = make_behavior("charge");
  TestSink sink;
  b->act(f.ctx(0), sink);
  // Object 20 (x=1) is a friend; the enemies are 30 at (0, 8) and 40 at (-5, 0): 40 is nearer.
  EXPECT_NEAR(sink.commands[0].move_x, -1.0f, 1e-5f);
  EXPECT_NEAR(sink.commands[0].move_y, 0.0f, 1e-5f);
  EXPECT_NEAR(std::abs(sink.commands[0].facing_rad), protocol::kPi, 1e-5);
}

TEST(Behavior, WaypointsCircleTheSpawn) {
  Fixture f;
  auto b = make_behavior("waypoints");
  TestSink sink;
  double max_dist = 0;
  for (int t = 0; t < 3000; ++t) {
    b->act(f.ctx(t / 30.0), sink);
    f.self.x += sink.commands.back().move_x * 0.15;
    f.self.y += sink.commands.back().move_y * 0.15;
    max_dist = std::max(max_dist, std::hypot(f.self.x, f.self.y));
  }
  EXPECT_GT(max_dist, 4.0);
  EXPECT_LT(max_dist, 7.5);  // the square's corners are at 5 * sqrt(2)
}

TEST(Behavior, NanSendsNonFiniteMoves) {
  Fixture f;
  auto b = make_behavior("nan");
  TestSink sink;
  for (int t = 0; t < 6; ++t) b->act(f.ctx(t / 30.0), sink);
  ASSERT_EQ(sink.commands.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_TRUE(std::isnan(sink.commands[i].move_x));
    EXPECT_EQ(sink.expects[i], Expect::reject);
  }
}

TEST(Behavior, FloodSendsTwentyPerTick) {
  Fixture f;
  auto b = make_behavior("flood");
  TestSink sink;
  b->act(f.ctx(0), sink);
  ASSERT_EQ(sink.commands.size(), 20u);
  EXPECT_EQ(sink.expects[0], Expect::accept);
  for (std::size_t i = 1; i < 20; ++i) EXPECT_EQ(sink.expects[i], Expect::unknown);
  for (const auto& c : sink.commands) {
    expect_valid(c);
    EXPECT_EQ(c.move_x, 0.0f);  // standing still: even the accepted ones change nothing
  }
}

TEST(Behavior, HijackCommandsAnotherClientsEntityElseAnNpc) {
  {
    Fixture f;
    auto b = make_behavior("hijack");
    TestSink sink;
    const std::vector<std::uint32_t> others{10, 77};
    b->act(f.ctx(0, others), sink);
    ASSERT_EQ(sink.commands.size(), 1u);
    EXPECT_EQ(sink.commands[0].entity, 77u);
    EXPECT_EQ(sink.expects[0], Expect::reject);
  }
  {
    Fixture f;
    auto b = make_behavior("hijack");
    TestSink sink;
    b->act(f.ctx(0), sink);
    const auto e = sink.commands[0].entity;
    EXPECT_NE(e, 10u);
    EXPECT_TRUE(e == 20 || e == 30 || e == 40) << e;
  }
}

TEST(Behavior, StaleReplaysOldSequenceNumbers) {
  Fixture f;
  auto b = make_behavior("stale");
  TestSink sink;
  for (int t = 0; t < 40; ++t) b->act(f.ctx(t / 30.0), sink);
  ASSERT_EQ(sink.commands.size(), 40u);
  std::uint32_t honest_max = 0;
  for (std::size_t i = 0; i < 40; ++i) {
    if (sink.expects[i] == Expect::accept) {
      EXPECT_EQ(sink.commands[i].move_x, 0.0f);
      honest_max = std::max(honest_max, sink.commands[i].sequence);
    } else {
      EXPECT_EQ(sink.expects[i], Expect::reject);
      EXPECT_LE(sink.commands[i].sequence, honest_max) << "a replay is never newer than what was sent";
      EXPECT_GT(sink.commands[i].move_x, 0.5f);
    }
  }
  EXPECT_EQ(honest_max, 15u);
}

}  // namespace
}  // namespace throng::client_sim
