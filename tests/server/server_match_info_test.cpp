// A late joiner still gets the match info (reliable + transient-local) and the entity each
// earlier client controls.
#include <gtest/gtest.h>

#include "server_test_support.h"

namespace throng::test {
namespace {

TEST(ServerMatchInfo, LateJoinerGetsTheMatchInfoAndEarlierAssignments) {
  ServerThread server(small_server_options(144));
  TestClient early(144);
  const auto r = early.join(11, "early");
  ASSERT_TRUE(r && r->result == protocol::JoinResult::accepted);
  ASSERT_TRUE(early.wait_until([&] { return early.snapshots().size() >= 10; }));  // the match has been running a while

  TestClient late(144);  // created after the match info and the join reply were published
  ASSERT_TRUE(late.wait_until([&] { return !late.match_infos().empty(); })) << "late joiner got no match info";
  const auto info = late.with_lock([&] { return late.match_infos().back(); });
  EXPECT_EQ(info.protocol_version, protocol::kProtocolVersion);
  EXPECT_EQ(info.scene_name, "battle");
  EXPECT_EQ(info.tick_hz, 30u);
  EXPECT_EQ(info.roster.id.size(), 400u);  // --npcs 400
  EXPECT_EQ(info.roster.radius_mm.size(), 400u);
  EXPECT_EQ(info.roster.faction.size(), 400u);
  EXPECT_EQ(info.scenery.size(), 7u);      // the battle scene's walls, tower and bushes
  EXPECT_GT(info.world_max_x, info.world_min_x);
  bool has_soft = false;
  for (const auto& s : info.scenery) has_soft |= s.softness > 0.0f;
  EXPECT_TRUE(has_soft) << "the bushes should be soft";
  ASSERT_TRUE(late.wait_until([&] {
    for (const auto& x : late.replies())
      if (x.client_nonce == 11) return true;
    return false;
  })) << "late joiner does not learn which entity the early client controls";
  const auto seen = late.with_lock([&] {
    for (const auto& x : late.replies())
      if (x.client_nonce == 11) return x;
    return protocol::JoinReply{};
  });
  EXPECT_EQ(seen.entity, r->entity);
}

}  // namespace
}  // namespace throng::test
