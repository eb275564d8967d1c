#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "match_test_util.h"
#include "throng/match/match.h"
#include "throng/params/object_params.h"
#include "throng/world/world.h"

namespace throng::match {
namespace {

using test::command;
using test::join_request;
using test::small_config;
using test::two_armies;

std::uint64_t rejected(const Match& m, RejectReason r) { return m.rejected_by_reason()[static_cast<std::size_t>(r)]; }

// Two identical matches with two clients each; A also receives one bad command per reason.
TEST(MatchCommands, EveryRejectReasonCountedOnceAndChangesNothing) {
  Match a(two_armies(), small_config(), "a");
  Match b(two_armies(), small_config(), "b");
  Outbox out_a, out_b;
  for (Match* m : {&a, &b}) {
    m->inputs().push(join_request(1));
    m->inputs().push(join_request(2));
  }
  a.tick(out_a);
  b.tick(out_b);
  ASSERT_EQ(out_a.join_replies.size(), 2u);
  const std::uint32_t e1 = out_a.join_replies[0].entity;
  const std::uint32_t e2 = out_a.join_replies[1].entity;
  ASSERT_EQ(e1, out_b.join_replies[0].entity);
  const float nan = std::numeric_limits<float>::quiet_NaN();

  std::uint32_t rejected_reported = 0;
  for (int t = 2; t <= 60; ++t) {
    std::vector<protocol::Command> good, bad;
    if (t == 2) {
      good.push_back(command(1, e1, 1, 0.0f, 1.0f));
      good.push_back(command(2, e2, 1, -1.0f, 0.0f));
      bad.push_back(command(9, e1, 2, 0.5f, 0.0f));       // unknown_client
      bad.push_back(command(1, e2, 2, 0.5f, 0.0f));       // not_your_entity
      bad.push_back(command(1, e1, 3, nan, 0.0f));        // non_finite
      bad.push_back(command(1, e1, 4, 1.0f, 1.0f));       // move_out_of_range
      protocol::Command facing = command(1, e1, 5, 0.5f, 0.0f);
      facing.facing_rad = 4.0f;                            // facing_out_of_range
      bad.push_back(facing);
      protocol::Command camera = command(1, e1, 6, 0.5f, 0.0f);
      camera.camera_x = 2.0e4f;                            // camera_out_of_range (limit 1e4)
      bad.push_back(camera);
      protocol::Command actions = command(1, e1, 7, 0.5f, 0.0f);
      actions.actions = 1u << 7;                           // bad_actions
      bad.push_back(actions);
      protocol::Command foreign = command(1, e1, 8, 1.0f, 0.0f);
      foreign.sender.bytes[0] = 7;                         // foreign_participant: client 1 joined from
      bad.push_back(foreign);                              //   the all-zero participant
    } else if (t == 3) {
      good.push_back(command(1, e1, 5, 1.0f, 0.0f));
    } else if (t == 4) {
      bad.push_back(command(1, e1, 4, -1.0f, 0.0f));      // stale_sequence
      bad.push_back(command(1, e1, 5, 0.0f, -1.0f));      // duplicate_sequence
    } else if (t == 5) {
      for (std::uint32_t s = 10; s <= 13; ++s) good.push_back(command(1, e1, s, 0.2f * float(s - 9), 0.0f));
      bad.push_back(command(1, e1, 14, -1.0f, 0.0f));     // rate_limited (5th in one tick)
    } else if (t == 6) {
      good.push_back(command(2, e2, 2, 0.0f, -1.0f));
    }
    for (const auto& c : good) {
      a.inputs().push(protocol::Command(c));
      b.inputs().push(protocol::Command(c));
    }
    for (const auto& c : bad) a.inputs().push(protocol::Command(c));
    const TickReport& ra = a.tick(out_a);
    const TickReport& rb = b.tick(out_b);
    EXPECT_EQ(ra.commands_accepted, rb.commands_accepted) << "tick " << t;
    EXPECT_EQ(ra.commands_rejected, bad.size()) << "tick " << t;
    rejected_reported += ra.commands_rejected;
    ASSERT_EQ(ra.state_hash, rb.state_hash) << "tick " << t;
    ASSERT_EQ(out_a.snapshot_count, 2u);
    EXPECT_EQ(out_a.snapshots[0].last_applied_sequence, out_b.snapshots[0].last_applied_sequence);
    EXPECT_EQ(out_a.snapshots[0].last_applied_tick, out_b.snapshots[0].last_applied_tick);
  }
  EXPECT_EQ(rejected_reported, 11u);
  for (std::size_t r = 0; r < kRejectReasonCount; ++r) {
    EXPECT_EQ(a.rejected_by_reason()[r], 1u) << to_string(static_cast<RejectReason>(r));
    EXPECT_EQ(b.rejected_by_reason()[r], 0u);
  }
  EXPECT_EQ(a.commands_accepted_total(), b.commands_accepted_total());
  EXPECT_EQ(a.commands_accepted_total(), 8u);
  EXPECT_EQ(a.clients()[0].last_applied_sequence, 13u);
  EXPECT_EQ(a.state_hash(), b.state_hash());
  EXPECT_STREQ(to_string(RejectReason::rate_limited), "rate_limited");
}

TEST(MatchCommands, AcceptedCommandMovesTheEntityAndItKeepsItsVelocity) {
  MatchConfig config = small_config();
  Match m(two_armies(), config, "m");
  Outbox out;
  const protocol::JoinReply j = test::join_one(m, out, 1);
  const World& w = m.world();
  const ObjectId e{j.entity};
  const Vec3 start = w.position(e);
  protocol::Command c = command(j.client_id, j.entity, 1, 0.0f, 1.0f);
  c.facing_rad = 1.25f;
  m.inputs().push(std::move(c));
  m.tick(out);
  ASSERT_EQ(out.snapshot_count, 1u);
  EXPECT_EQ(out.snapshots[0].last_applied_sequence, 1u);
  EXPECT_EQ(out.snapshots[0].last_applied_tick, 2u);
  EXPECT_FLOAT_EQ(out.snapshots[0].entity_yaw, 1.25f);
  // No further commands: the entity keeps walking north (thin client).
  for (int t = 0; t < 59; ++t) m.tick(out);
  const Vec3 after = w.position(e);
  const double dy = after.y - start.y;
  const double dx = after.x - start.x;
  EXPECT_GT(dy, 0.6 * config.player_speed_mps * 2.0);  // 2 s at 4 m/s, minus pushes through the ranks
  EXPECT_LT(std::abs(dx), 0.25 * dy);
  // Own pose in the snapshot is the exact world pose.
  EXPECT_FLOAT_EQ(out.snapshots[0].entity_x, static_cast<float>(after.x));
  EXPECT_FLOAT_EQ(out.snapshots[0].entity_y, static_cast<float>(after.y));
  EXPECT_FLOAT_EQ(out.snapshots[0].entity_z, static_cast<float>(after.z));
  EXPECT_EQ(out.snapshots[0].tick, m.tick_index());
  // Out in the open now: full speed north.
  EXPECT_NEAR(w.velocity(e).y, config.player_speed_mps, 0.05);
  // Sprint: 1.5x.
  protocol::Command sprint = command(j.client_id, j.entity, 2, 0.0f, 1.0f);
  sprint.actions = protocol::kActionSprint;
  m.inputs().push(std::move(sprint));
  for (int t = 0; t < 5; ++t) m.tick(out);
  EXPECT_NEAR(w.velocity(e).y, 1.5 * config.player_speed_mps, 0.05);
  // Stop.
  m.inputs().push(command(j.client_id, j.entity, 3, 0.0f, 0.0f));
  m.tick(out);
  EXPECT_NEAR(w.velocity(e).y, 0.0, 1e-9);
}

TEST(MatchCommands, BraceDoublesTheWeightWhileHeld) {
  Match m(two_armies(), small_config(), "m");
  Outbox out;
  const protocol::JoinReply j = test::join_one(m, out, 1);
  const ObjectId e{j.entity};
  const double base = m.world().params(e).weight_kg;
  protocol::Command c = command(j.client_id, j.entity, 1);
  c.actions = protocol::kActionBrace;
  m.inputs().push(std::move(c));
  m.tick(out);
  EXPECT_DOUBLE_EQ(m.world().params(e).weight_kg, 2.0 * base);
  m.inputs().push(command(j.client_id, j.entity, 2));
  m.tick(out);
  EXPECT_DOUBLE_EQ(m.world().params(e).weight_kg, base);
  // Leaving while bracing restores the weight too.
  protocol::Command again = command(j.client_id, j.entity, 3);
  again.actions = protocol::kActionBrace;
  m.inputs().push(std::move(again));
  m.inputs().push(test::leave_request(1, j.client_id));
  m.tick(out);
  EXPECT_DOUBLE_EQ(m.world().params(e).weight_kg, base);
}

TEST(MatchCommands, RateLimitPerClientPerTickAndNewestWins) {
  MatchConfig config = small_config();
  config.max_commands_per_tick = 3;
  Match m(two_armies(), config, "m");
  Match twin(two_armies(), config, "twin");
  Outbox out, twin_out;
  const protocol::JoinReply j1 = test::join_one(m, out, 1);
  const protocol::JoinReply j2 = test::join_one(m, out, 2);
  test::join_one(twin, twin_out, 1);
  test::join_one(twin, twin_out, 2);
  for (std::uint32_t s = 1; s <= 6; ++s) m.inputs().push(command(j1.client_id, j1.entity, s, 0.1f * float(s), 0.0f));
  for (std::uint32_t s = 1; s <= 3; ++s) m.inputs().push(command(j2.client_id, j2.entity, s, 0.0f, 0.2f * float(s)));
  const TickReport& r = m.tick(out);
  EXPECT_EQ(r.commands_accepted, 6u);  // 3 + 3: the limit is per client
  EXPECT_EQ(r.commands_rejected, 3u);
  EXPECT_EQ(rejected(m, RejectReason::rate_limited), 3u);
  EXPECT_EQ(out.snapshots[0].last_applied_sequence, 3u);
  EXPECT_EQ(out.snapshots[1].last_applied_sequence, 3u);
  // The newest accepted command of the tick is the one in effect: same world as sending only it.
  twin.inputs().push(command(j1.client_id, j1.entity, 3, 0.3f, 0.0f));
  twin.inputs().push(command(j2.client_id, j2.entity, 3, 0.0f, 0.6f));
  EXPECT_EQ(twin.tick(twin_out).state_hash, r.state_hash);
  // Next tick: room again.
  m.inputs().push(command(j1.client_id, j1.entity, 7));
  EXPECT_EQ(m.tick(out).commands_accepted, 1u);
  EXPECT_EQ(out.snapshots[0].last_applied_sequence, 7u);
}

TEST(MatchCommands, StaleAndDuplicateSequences) {
  Match m(two_armies(), small_config(), "m");
  Outbox out;
  const protocol::JoinReply j = test::join_one(m, out, 1);
  m.inputs().push(command(j.client_id, j.entity, 0));  // sequences start at 1
  m.tick(out);
  EXPECT_EQ(rejected(m, RejectReason::stale_sequence), 1u);
  m.inputs().push(command(j.client_id, j.entity, 5));
  m.inputs().push(command(j.client_id, j.entity, 5));  // the same packet twice in one tick
  m.tick(out);
  EXPECT_EQ(rejected(m, RejectReason::duplicate_sequence), 1u);
  m.inputs().push(command(j.client_id, j.entity, 5));
  m.inputs().push(command(j.client_id, j.entity, 2));
  m.inputs().push(command(j.client_id, j.entity, 6));
  const TickReport& r = m.tick(out);
  EXPECT_EQ(r.commands_accepted, 1u);
  EXPECT_EQ(rejected(m, RejectReason::duplicate_sequence), 2u);
  EXPECT_EQ(rejected(m, RejectReason::stale_sequence), 2u);
  EXPECT_EQ(out.snapshots[0].last_applied_sequence, 6u);
}

TEST(MatchCommands, SlackOnMoveAndFacingLimits) {
  Match m(two_armies(), small_config(), "m");
  Outbox out;
  const protocol::JoinReply j = test::join_one(m, out, 1);
  protocol::Command c = command(j.client_id, j.entity, 1, 1.0005f, 0.0f);
  c.facing_rad = static_cast<float>(std::numbers::pi) + 0.0005f;
  c.camera_x = 1.0e4f;  // exactly the limit
  m.inputs().push(std::move(c));
  EXPECT_EQ(m.tick(out).commands_accepted, 1u);
}

TEST(MatchCommands, CameraFeedsTheEngineCameraDistance) {
  Match m(two_armies(), small_config(), "m");
  Outbox out;
  // A policy that reads the camera distance, so the engine computes it.
  protocol::ParamUpdate u;
  u.request_id = 1;
  u.policy_json = R"({"mode": "ratio", "terms": [{"param": "camera_distance_m", "weight": 1, "scale": 100}]})";
  m.inputs().push(std::move(u));
  const protocol::JoinReply j = test::join_one(m, out, 1);
  ASSERT_EQ(out.param_replies.size(), 1u);
  ASSERT_TRUE(out.param_replies[0].ok) << out.param_replies[0].error;
  protocol::Command c = command(j.client_id, j.entity, 1);
  c.camera_x = 100.0f;
  c.camera_y = 0.0f;
  c.camera_z = 0.0f;
  m.inputs().push(std::move(c));
  m.tick(out);
  m.tick(out);
  const World& w = m.world();
  for (std::size_t d = 0; d < w.body_count(); d += 7) {
    const ObjectId id = w.id_at(d);
    const double dist = std::hypot(w.pos_x()[d] - 100.0, w.pos_y()[d], w.pos_z()[d]);
    EXPECT_NEAR(w.params(id).camera_distance_m, dist, 0.5);
  }
}

}  // namespace
}  // namespace throng::match
