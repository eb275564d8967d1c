#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "throng/client_sim/client_world.h"
#include "throng/protocol/codec.h"

namespace throng::client_sim {
namespace {

using protocol::Pose;
using protocol::Snapshot;

Snapshot snap(std::uint64_t tick, std::vector<Pose> poses, std::vector<std::uint32_t> removed = {}) {
  Snapshot s;
  s.client_id = 1;
  s.tick = tick;
  EXPECT_TRUE(protocol::encode_poses(poses, 0, 0, 1, s));
  s.removed = std::move(removed);
  return s;
}

std::shared_ptr<const MatchView> match_at(std::uint32_t hz) {
  protocol::MatchInfo info;
  info.tick_hz = hz;
  return std::make_shared<const MatchView>(info);
}

TEST(ClientWorld, InterpolatesTwoTicksBehindTheNewest) {
  ClientWorld w;
  ASSERT_EQ(w.apply(snap(10, {{5, 0.0, 0.0, 0.0, 0.0}})), ClientWorld::ApplyResult::applied);
  ASSERT_EQ(w.apply(snap(11, {{5, 1.0, 2.0, 0.0, 0.0}})), ClientWorld::ApplyResult::applied);
  ASSERT_EQ(w.apply(snap(12, {{5, 2.0, 4.0, 0.0, 0.0}})), ClientWorld::ApplyResult::applied);
  EXPECT_DOUBLE_EQ(w.render_tick(), 10.0);
  auto p = w.object(5);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x, 0.0, 1e-9);
  p = w.object_at(5, 10.5);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x, 0.5, 1e-9);
  EXPECT_NEAR(p->y, 1.0, 1e-9);
  p = w.object_at(5, 11.75);
  EXPECT_NEAR(p->x, 1.75, 1e-9);
  EXPECT_NEAR(p->y, 3.5, 1e-9);
  // After the newest sample the newest is held; before the oldest, the oldest.
  EXPECT_NEAR(w.object_at(5, 20.0)->x, 2.0, 1e-9);
  EXPECT_NEAR(w.object_at(5, 3.0)->x, 0.0, 1e-9);
  // Only the last three samples are kept.
  w.apply(snap(13, {{5, 3.0, 6.0, 0.0, 0.0}}));
  EXPECT_NEAR(w.object_at(5, 10.0)->x, 1.0, 1e-9);  // oldest is now tick 11
  EXPECT_NEAR(w.object(5)->x, 1.0, 1e-9);           // render tick 11
}

TEST(ClientWorld, InterpolatesAcrossUnsentTicksAndYawTheShortWay) {
  ClientWorld w;
  w.apply(snap(100, {{9, 0.0, 0.0, 0.0, 3.0}}));
  w.apply(snap(110, {{9, 10.0, 0.0, 0.0, -3.0}}));  // ticks 101..109 did not carry object 9
  auto p = w.object_at(9, 105.0);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x, 5.0, 1e-9);
  // 3.0 and -3.0 rad are 0.28 rad apart through pi: the midpoint is near +-pi, not 0.
  EXPECT_GT(std::abs(p->yaw), 3.0);
}

TEST(ClientWorld, RemovedObjectsGoAtOnce) {
  ClientWorld w;
  w.apply(snap(1, {{3, 1, 1, 0, 0}, {4, 2, 2, 0, 0}}));
  EXPECT_EQ(w.object_count(), 2u);
  w.apply(snap(2, {}, {3}));
  EXPECT_FALSE(w.object(3));
  EXPECT_TRUE(w.object(4));
  EXPECT_EQ(w.object_count(), 1u);
  // Removing an unknown id is harmless.
  EXPECT_EQ(w.apply(snap(3, {}, {77})), ClientWorld::ApplyResult::applied);
}

TEST(ClientWorld, ObjectsExpireAfterThreeSecondsUnseen) {
  ClientWorld w;
  w.set_match(match_at(10));  // 3 s = 30 ticks
  w.apply(snap(1, {{3, 1, 1, 0, 0}, {4, 2, 2, 0, 0}}));
  for (std::uint64_t t = 2; t <= 31; ++t) w.apply(snap(t, {{4, 2, 2, 0, 0}}));
  EXPECT_TRUE(w.object(3)) << "30 ticks unseen: not yet expired";
  w.apply(snap(32, {{4, 2, 2, 0, 0}}));
  EXPECT_FALSE(w.object(3));
  EXPECT_TRUE(w.object(4));
  EXPECT_EQ(w.object_count(), 1u);
  int seen = 0;
  w.for_each([&](const ObjectState& o) {
    ++seen;
    EXPECT_EQ(o.id, 4u);
  });
  EXPECT_EQ(seen, 1);
}

TEST(ClientWorld, OwnEntityFromUnquantizedFields) {
  ClientWorld w;
  Snapshot s = snap(5, {{7, 1.0, 1.0, 0.0, 0.0}});
  s.entity = 7;
  s.entity_x = 1.2345f;
  s.entity_y = -2.5f;
  s.entity_z = 0.25f;
  s.entity_yaw = 0.5f;
  ASSERT_EQ(w.apply(s), ClientWorld::ApplyResult::applied);
  EXPECT_EQ(w.own_entity(), 7u);
  ASSERT_TRUE(w.own_pose());
  EXPECT_NEAR(w.own_pose()->x, 1.2345, 1e-6);
  // The unquantized pose overrides the quantized copy of the same tick.
  EXPECT_NEAR(w.object_at(7, 5.0)->x, 1.2345, 1e-6);
  EXPECT_NEAR(w.object_at(7, 5.0)->y, -2.5, 1e-6);
}

TEST(ClientWorld, MalformedSnapshotsAreCountedAndDropped) {
  ClientWorld w;
  ASSERT_EQ(w.apply(snap(1, {{3, 1, 1, 0, 0}})), ClientWorld::ApplyResult::applied);

  Snapshot lengths = snap(2, {{3, 5, 5, 0, 0}});
  lengths.y.push_back(1);  // arrays disagree
  EXPECT_EQ(w.apply(lengths), ClientWorld::ApplyResult::malformed);

  Snapshot escape = snap(3, {{3, 5, 5, 0, 0}});
  escape.id_codes = {0, 1};  // truncated escape
  EXPECT_EQ(w.apply(escape), ClientWorld::ApplyResult::malformed);

  Snapshot unit = snap(4, {{3, 5, 5, 0, 0}});
  unit.unit_mm = 0;
  EXPECT_EQ(w.apply(unit), ClientWorld::ApplyResult::malformed);

  Snapshot order = snap(5, {{3, 5, 5, 0, 0}, {4, 5, 5, 0, 0}});
  order.id_codes = {0, 0, 9, 0, 0, 2};  // escape ids 9 then 2: not ascending
  EXPECT_EQ(w.apply(order), ClientWorld::ApplyResult::malformed);

  Snapshot extra = snap(6, {{3, 5, 5, 0, 0}});
  extra.id_codes.push_back(1);  // more codes than poses
  EXPECT_EQ(w.apply(extra), ClientWorld::ApplyResult::malformed);

  Snapshot nan_own = snap(7, {});
  nan_own.entity = 3;
  nan_own.entity_x = std::nanf("");
  EXPECT_EQ(w.apply(nan_own), ClientWorld::ApplyResult::malformed);

  EXPECT_EQ(w.malformed_count(), 6u);
  EXPECT_FALSE(w.last_error().empty());
  // Nothing of them reached the world.
  EXPECT_EQ(*w.newest_tick(), 1u);
  EXPECT_NEAR(w.object_at(3, 1.0)->x, 1.0, 1e-9);
  // and the next good one applies.
  EXPECT_EQ(w.apply(snap(8, {{3, 2, 2, 0, 0}})), ClientWorld::ApplyResult::applied);
  EXPECT_EQ(w.applied_count(), 2u);
}

TEST(ClientWorld, OldOrDuplicateTicksAreStale) {
  ClientWorld w;
  w.apply(snap(10, {{3, 1, 1, 0, 0}}));
  EXPECT_EQ(w.apply(snap(10, {{3, 9, 9, 0, 0}})), ClientWorld::ApplyResult::stale);
  EXPECT_EQ(w.apply(snap(9, {{3, 9, 9, 0, 0}})), ClientWorld::ApplyResult::stale);
  EXPECT_EQ(w.stale_count(), 2u);
  EXPECT_NEAR(w.object_at(3, 10.0)->x, 1.0, 1e-9);
}

TEST(ClientWorld, RosterFromMatchInfo) {
  protocol::MatchInfo info;
  info.tick_hz = 60;
  info.roster.id = {1, 2, 3};
  info.roster.radius_mm = {300, 350, 400};
  info.roster.half_height_mm = {0, 0, 500};
  info.roster.faction = {0, 1, 1};
  info.roster.character_type = {0, 0, 1};
  info.roster.archetype = {0, 0, 0};
  MatchView v(info);
  EXPECT_EQ(v.tick_hz(), 60u);
  ASSERT_TRUE(v.find(2));
  EXPECT_EQ(v.find(2)->faction, 1);
  EXPECT_EQ(v.find(3)->half_height_mm, 500);
  EXPECT_FALSE(v.find(4));
  // Mismatched arrays are cut, never read out of bounds.
  info.roster.faction.pop_back();
  MatchView cut(info);
  EXPECT_EQ(cut.ids().size(), 2u);
  EXPECT_FALSE(cut.find(3));
}

}  // namespace
}  // namespace throng::client_sim
