#include <gtest/gtest.h>

#include "match_test_util.h"
#include "throng/match/match.h"
#include "throng/params/categories.h"
#include "throng/params/object_params.h"
#include "throng/world/world.h"

namespace throng::match {
namespace {

TEST(MatchTimeout, ClientDroppedAfterExactlyTheConfiguredTicks) {
  MatchConfig config = test::small_config();
  config.tick_hz = 30;
  config.client_timeout_s = 0.5;  // 15 ticks
  Match m(test::two_armies(), config, "m");
  Outbox out;
  const protocol::JoinReply j = test::join_one(m, out, 1);  // tick 1
  ASSERT_EQ(j.tick, 1u);
  for (std::uint64_t t = 2; t <= 15; ++t) {
    const TickReport& r = m.tick(out);
    ASSERT_EQ(r.timeouts, 0u) << "tick " << t;
    ASSERT_EQ(m.client_count(), 1u) << "tick " << t;
  }
  const TickReport& r = m.tick(out);  // tick 16 = 15 ticks after the join
  EXPECT_EQ(r.tick, 16u);
  EXPECT_EQ(r.timeouts, 1u);
  EXPECT_EQ(m.client_count(), 0u);
  ASSERT_EQ(out.client_events.size(), 1u);
  EXPECT_EQ(out.client_events[0].kind, ClientEvent::Kind::timed_out);
  EXPECT_EQ(out.client_events[0].client_id, j.client_id);
  EXPECT_EQ(out.client_events[0].partition, "c1");
  ASSERT_EQ(out.join_replies.size(), 1u);
  EXPECT_EQ(out.join_replies[0].result, protocol::JoinResult::left);
  EXPECT_EQ(out.snapshot_count, 0u);
  EXPECT_EQ(m.world().params(ObjectId{j.entity}).character_type, params::CharacterType::npc);
  // Its commands are now from an unknown client.
  m.inputs().push(test::command(j.client_id, j.entity, 1));
  EXPECT_EQ(m.tick(out).commands_rejected, 1u);
  EXPECT_EQ(m.rejected_by_reason()[static_cast<std::size_t>(RejectReason::unknown_client)], 1u);
}

TEST(MatchTimeout, AcceptedCommandsKeepTheClientAliveRejectedOnesDoNot) {
  MatchConfig config = test::small_config();
  config.client_timeout_s = 0.5;  // 15 ticks at 30 Hz
  Match m(test::two_armies(), config, "m");
  Outbox out;
  const protocol::JoinReply j = test::join_one(m, out, 1);  // tick 1
  for (int t = 2; t < 10; ++t) m.tick(out);
  m.inputs().push(test::command(j.client_id, j.entity, 1, 1.0f, 0.0f));  // tick 10: accepted
  m.tick(out);
  for (int t = 11; t < 20; ++t) m.tick(out);
  // Rejected commands (bad entity, bad move) do not count as activity.
  m.inputs().push(test::command(j.client_id, j.entity + 1, 2));
  m.inputs().push(test::command(j.client_id, j.entity, 3, 2.0f, 0.0f));
  m.tick(out);  // tick 20
  for (int t = 21; t < 25; ++t) {
    m.tick(out);
    ASSERT_EQ(m.client_count(), 1u) << "tick " << t;
  }
  // The entity was walking east; when it times out it stops before the AI takes it back.
  const TickReport& r = m.tick(out);  // tick 25 = 15 after the last accepted command
  EXPECT_EQ(r.timeouts, 1u);
  EXPECT_EQ(m.client_count(), 0u);
}

}  // namespace
}  // namespace throng::match
