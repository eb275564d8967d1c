#include <nlohmann/json.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "match_test_util.h"
#include "throng/match/match.h"
#include "throng/params/categories.h"
#include "throng/params/object_params.h"
#include "throng/world/world.h"

namespace throng::match {
namespace {

using protocol::JoinResult;
using test::join_request;
using test::leave_request;
using test::small_config;
using test::two_armies;

const params::ObjectParams& params_of(const Match& m, std::uint32_t entity) {
  return m.world().params(ObjectId{entity});
}

TEST(MatchJoin, AcceptedClientTakesOverTheNpcNearestItsFactionCentroid) {
  Match m(two_armies(), small_config(), "m1");
  Outbox out;
  // Expected: the faction-1 body closest to the faction-1 centroid (ties: lower id).
  const World& w = m.world();
  double sx = 0, sy = 0;
  int count = 0;
  for (std::size_t d = 0; d < w.body_count(); ++d) {
    if (w.params(w.id_at(d)).faction != 1) continue;
    sx += w.pos_x()[d];
    sy += w.pos_y()[d];
    ++count;
  }
  std::uint32_t expected = 0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t d = 0; d < w.body_count(); ++d) {
    if (w.params(w.id_at(d)).faction != 1) continue;
    const double dx = w.pos_x()[d] - sx / count, dy = w.pos_y()[d] - sy / count;
    if (dx * dx + dy * dy < best) {
      best = dx * dx + dy * dy;
      expected = w.id_at(d).value;
    }
  }

  m.inputs().push(join_request(77, "alice"));
  const TickReport& r = m.tick(out);
  EXPECT_EQ(r.joins_accepted, 1u);
  ASSERT_EQ(out.join_replies.size(), 1u);
  const protocol::JoinReply& reply = out.join_replies[0];
  EXPECT_EQ(reply.result, JoinResult::accepted);
  EXPECT_EQ(reply.client_nonce, 77u);
  EXPECT_EQ(reply.client_id, 1u);
  EXPECT_EQ(reply.entity, expected);
  EXPECT_EQ(reply.faction, 1);
  EXPECT_EQ(reply.snapshot_partition, "c1");
  EXPECT_EQ(reply.tick, 1u);
  ASSERT_EQ(out.client_events.size(), 1u);
  EXPECT_EQ(out.client_events[0].kind, ClientEvent::Kind::joined);
  EXPECT_EQ(out.client_events[0].client_id, 1u);
  EXPECT_EQ(out.client_events[0].entity, expected);
  EXPECT_EQ(out.client_events[0].partition, "c1");
  EXPECT_EQ(out.client_events[0].name, "alice");
  EXPECT_EQ(m.client_count(), 1u);
  EXPECT_EQ(m.npc_count(), 39u);
  // The new client gets a snapshot in the same tick.
  ASSERT_EQ(out.snapshot_count, 1u);
  EXPECT_EQ(out.snapshots[0].client_id, 1u);
  EXPECT_EQ(out.snapshots[0].entity, expected);
  EXPECT_EQ(out.snapshots[0].tick, 1u);

  // Second client: the other faction.
  const protocol::JoinReply second = test::join_one(m, out, 78, "bob");
  EXPECT_EQ(second.result, JoinResult::accepted);
  EXPECT_EQ(second.client_id, 2u);
  EXPECT_EQ(second.faction, 2);
  EXPECT_EQ(second.snapshot_partition, "c2");
  EXPECT_NE(second.entity, expected);
  // Third: faction 1 again, a different body.
  const protocol::JoinReply third = test::join_one(m, out, 79, "carol");
  EXPECT_EQ(third.faction, 1);
  EXPECT_NE(third.entity, expected);
  const auto summary = m.clients();
  ASSERT_EQ(summary.size(), 3u);
  EXPECT_EQ(summary[0].client_id, 1u);
  EXPECT_EQ(summary[2].name, "carol");
  EXPECT_EQ(summary[2].joined_tick, 3u);
}

TEST(MatchJoin, FactionWithoutFreeNpcPassesToTheOther) {
  Match m(two_armies(1, 30.0, 1.0), small_config(), "m1");  // one body per faction
  Outbox out;
  EXPECT_EQ(test::join_one(m, out, 1).faction, 1);  // client 1
  const protocol::JoinReply c2 = test::join_one(m, out, 2);
  EXPECT_EQ(c2.faction, 2);  // client 2
  const protocol::JoinReply full = test::join_one(m, out, 3);
  EXPECT_EQ(full.result, JoinResult::match_full);  // no free character at all
  EXPECT_FALSE(full.reason.empty());
  // Client 2 leaves; the next client (id 3) prefers faction 1, which has no free body: it gets
  // faction 2's.
  m.inputs().push(leave_request(2, c2.client_id));
  m.tick(out);
  const protocol::JoinReply c3 = test::join_one(m, out, 4);
  EXPECT_EQ(c3.result, JoinResult::accepted);
  EXPECT_EQ(c3.client_id, 3u);  // ids are never reused (the refused join got none)
  EXPECT_EQ(c3.faction, 2);
  EXPECT_EQ(c3.entity, c2.entity);
}

TEST(MatchJoin, RefusalReasons) {
  MatchConfig config = small_config();
  config.max_clients = 1;
  Match m(two_armies(), config, "m1");
  Outbox out;

  protocol::JoinRequest bad_version = join_request(5);
  bad_version.protocol_version = protocol::kProtocolVersion + 6;
  m.inputs().push(std::move(bad_version));
  m.inputs().push(join_request(0));                       // nonce 0
  m.inputs().push(join_request(6, std::string(65, 'x')));  // name too long
  m.inputs().push(leave_request(8, 42));                   // leave for an unknown client
  const TickReport& r = m.tick(out);
  EXPECT_EQ(r.joins_refused, 4u);
  EXPECT_EQ(r.joins_accepted, 0u);
  ASSERT_EQ(out.join_replies.size(), 4u);
  // Sorted by nonce: 0, 5, 6, 8.
  EXPECT_EQ(out.join_replies[0].result, JoinResult::bad_request);
  EXPECT_EQ(out.join_replies[1].result, JoinResult::bad_version);
  const std::string& why = out.join_replies[1].reason;
  EXPECT_NE(why.find(std::to_string(protocol::kProtocolVersion + 6)), std::string::npos) << why;
  EXPECT_NE(why.find(std::to_string(protocol::kProtocolVersion)), std::string::npos) << why;
  EXPECT_EQ(out.join_replies[2].result, JoinResult::bad_request);
  EXPECT_NE(out.join_replies[2].reason.find("65"), std::string::npos);
  EXPECT_EQ(out.join_replies[3].result, JoinResult::bad_request);
  EXPECT_TRUE(out.client_events.empty());
  EXPECT_EQ(m.client_count(), 0u);

  // A 64-byte name is fine; the match is then full.
  EXPECT_EQ(test::join_one(m, out, 20, std::string(64, 'y')).result, JoinResult::accepted);
  const protocol::JoinReply full = test::join_one(m, out, 21);
  EXPECT_EQ(full.result, JoinResult::match_full);
  EXPECT_EQ(full.client_id, 0u);

  // Shutting down beats full; the duplicate of a connected nonce still gets its reply.
  m.begin_shutdown();
  m.inputs().push(join_request(22));
  m.inputs().push(join_request(20, std::string(64, 'y')));
  m.tick(out);
  ASSERT_EQ(out.join_replies.size(), 2u);
  EXPECT_EQ(out.join_replies[0].client_nonce, 20u);
  EXPECT_EQ(out.join_replies[0].result, JoinResult::accepted);
  EXPECT_EQ(out.join_replies[1].result, JoinResult::shutting_down);
  EXPECT_TRUE(out.match_info_changed);
  EXPECT_EQ(m.match_info().state, protocol::MatchState::ended);
}

TEST(MatchJoin, DuplicateJoinIsIdempotent) {
  Match m(two_armies(), small_config(), "m1");
  Outbox out;
  const protocol::JoinReply first = test::join_one(m, out, 99, "dup");
  m.tick(out);
  m.inputs().push(join_request(99, "dup"));
  const TickReport& r = m.tick(out);
  ASSERT_EQ(out.join_replies.size(), 1u);
  const protocol::JoinReply& again = out.join_replies[0];
  EXPECT_EQ(again.result, JoinResult::accepted);
  EXPECT_EQ(again.client_id, first.client_id);
  EXPECT_EQ(again.entity, first.entity);
  EXPECT_EQ(again.snapshot_partition, first.snapshot_partition);
  EXPECT_EQ(again.tick, first.tick);
  EXPECT_EQ(again.faction, first.faction);
  EXPECT_TRUE(out.client_events.empty());
  EXPECT_EQ(r.joins_accepted, 0u);
  EXPECT_EQ(m.client_count(), 1u);
}

// A client belongs to the participant that joined it: another participant that learnt its nonce
// and id (both are in the public join reply) can neither make it leave nor get its reply again.
// Those requests are counted, answered with nothing (a refusal keyed by the owner's nonce would
// replace the owner's reply) and change nothing: the state hash follows a twin without them.
TEST(MatchJoin, ForeignParticipantCannotLeaveOrRejoinSomeoneElsesClient) {
  protocol::ParticipantKey owner, stranger;
  owner.bytes = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  stranger.bytes = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 13};
  Match a(two_armies(), small_config(), "a");
  Match b(two_armies(), small_config(), "b");
  Outbox out_a, out_b;
  for (Match* m : {&a, &b}) {
    protocol::JoinRequest j = join_request(500, "victim");
    j.sender = owner;
    m->inputs().push(std::move(j));
  }
  a.tick(out_a);
  b.tick(out_b);
  ASSERT_EQ(out_a.join_replies.size(), 1u);
  const std::uint32_t id = out_a.join_replies[0].client_id;

  protocol::JoinRequest leave = leave_request(500, id);
  leave.sender = stranger;
  protocol::JoinRequest rejoin = join_request(500, "victim");
  rejoin.sender = stranger;
  a.inputs().push(std::move(leave));
  a.inputs().push(std::move(rejoin));
  const TickReport& r = a.tick(out_a);
  b.tick(out_b);
  EXPECT_EQ(r.joins_foreign, 2u);
  EXPECT_EQ(r.leaves, 0u);
  EXPECT_EQ(r.joins_refused, 0u);
  EXPECT_TRUE(out_a.join_replies.empty());
  EXPECT_TRUE(out_a.client_events.empty());
  EXPECT_EQ(a.client_count(), 1u);
  EXPECT_EQ(a.state_hash(), b.state_hash());

  // The owner still can.
  protocol::JoinRequest own_leave = leave_request(500, id);
  own_leave.sender = owner;
  a.inputs().push(std::move(own_leave));
  const TickReport& r2 = a.tick(out_a);
  EXPECT_EQ(r2.leaves, 1u);
  EXPECT_EQ(r2.joins_foreign, 0u);
  ASSERT_EQ(out_a.join_replies.size(), 1u);
  EXPECT_EQ(out_a.join_replies[0].result, JoinResult::left);
  EXPECT_EQ(a.client_count(), 0u);
}

// With an authenticated identity the partition is named after it, so a player's permissions can
// grant it before the join; without one it stays c<id>.
TEST(MatchJoin, PartitionFollowsTheAuthenticatedIdentity) {
  Match m(two_armies(), small_config(), "m1");
  Outbox out;
  protocol::JoinRequest alice = join_request(1, "alice");
  alice.identity = "player-alice";
  m.inputs().push(std::move(alice));
  m.inputs().push(join_request(2, "anon"));
  m.tick(out);
  ASSERT_EQ(out.join_replies.size(), 2u);
  EXPECT_EQ(out.join_replies[0].snapshot_partition, "throng_p_player-alice_1");
  EXPECT_EQ(out.join_replies[1].snapshot_partition, "c2");
}

TEST(MatchJoin, TakeoverSetsPlayerParamsAndLeaveRestoresThem) {
  Match m(two_armies(), small_config(), "m1");
  Outbox out;
  m.tick(out);
  // Remember every body's parameters before the takeover.
  const World& w = m.world();
  const protocol::JoinReply reply = test::join_one(m, out, 5);
  const std::uint32_t e = reply.entity;
  EXPECT_EQ(params_of(m, e).character_type, params::CharacterType::player);
  EXPECT_DOUBLE_EQ(params_of(m, e).importance, 8.0);  // built-in table: no "player" archetype
  EXPECT_EQ(m.npc_count(), 39u);

  // The entity walks under the client's command; then the client leaves.
  m.inputs().push(test::command(reply.client_id, e, 1, 1.0f, 0.0f));
  m.tick(out);
  EXPECT_GT(w.velocity(ObjectId{e}).x, 1.0);
  m.inputs().push(leave_request(5, reply.client_id));
  const TickReport& r = m.tick(out);
  EXPECT_EQ(r.leaves, 1u);
  ASSERT_EQ(out.join_replies.size(), 1u);
  EXPECT_EQ(out.join_replies[0].result, JoinResult::left);
  EXPECT_EQ(out.join_replies[0].client_id, reply.client_id);
  EXPECT_EQ(out.join_replies[0].entity, e);
  ASSERT_EQ(out.client_events.size(), 1u);
  EXPECT_EQ(out.client_events[0].kind, ClientEvent::Kind::left);
  EXPECT_EQ(out.client_events[0].entity, e);
  EXPECT_EQ(out.snapshot_count, 0u);
  EXPECT_EQ(params_of(m, e).character_type, params::CharacterType::npc);
  EXPECT_DOUBLE_EQ(params_of(m, e).importance, 1.0);
  EXPECT_EQ(m.client_count(), 0u);
  EXPECT_EQ(m.npc_count(), 40u);

  // A repeated leave is answered `left` again, without a second event. The match no longer holds
  // the client's record, so it cannot tell the repeat from any other leave naming a departed id:
  // each gets the same answer, which changes nothing.
  for (std::uint64_t nonce : {5u, 6u}) {
    m.inputs().push(leave_request(nonce, reply.client_id));
    const TickReport& again = m.tick(out);
    ASSERT_EQ(out.join_replies.size(), 1u);
    EXPECT_EQ(out.join_replies[0].result, JoinResult::left);
    EXPECT_EQ(out.join_replies[0].client_nonce, nonce);
    EXPECT_EQ(out.join_replies[0].client_id, reply.client_id);
    EXPECT_EQ(out.join_replies[0].entity, 0u);
    EXPECT_NE(out.join_replies[0].reason.find("not connected"), std::string::npos) << out.join_replies[0].reason;
    EXPECT_TRUE(out.client_events.empty());
    EXPECT_EQ(again.leaves, 0u);
  }
  // An id never given out is refused.
  m.inputs().push(leave_request(7, reply.client_id + 1));
  m.tick(out);
  ASSERT_EQ(out.join_replies.size(), 1u);
  EXPECT_EQ(out.join_replies[0].result, JoinResult::bad_request);
}

// A leave that carries a connected client's nonce but comes from another participant is never
// answered, whatever client id it names (its own, a departed one, one never given out): every
// answer is published on the nonce's key and would replace the connected client's accepted reply.
TEST(MatchJoin, ALeaveOnSomeoneElsesNonceIsNeverAnswered) {
  protocol::ParticipantKey owner, stranger;
  owner.bytes = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  stranger.bytes = {9, 9, 9, 4, 5, 6, 7, 8, 9, 10, 11, 13};
  Match m(two_armies(), small_config(), "m");
  Outbox out;
  const protocol::JoinReply gone = test::join_one(m, out, 77);
  m.inputs().push(leave_request(77, gone.client_id));
  m.tick(out);
  protocol::JoinRequest j = join_request(500, "victim");
  j.sender = owner;
  m.inputs().push(std::move(j));
  m.tick(out);
  ASSERT_EQ(out.join_replies.size(), 1u);
  const std::uint32_t victim = out.join_replies[0].client_id;
  for (std::uint32_t named : {gone.client_id, victim + 100}) {
    protocol::JoinRequest leave = leave_request(500, named);
    leave.sender = stranger;
    m.inputs().push(std::move(leave));
    const TickReport& r = m.tick(out);
    EXPECT_TRUE(out.join_replies.empty()) << "client " << named << ": " << out.join_replies[0].reason;
    EXPECT_EQ(r.joins_foreign, 1u);
    EXPECT_EQ(r.joins_refused, 0u);
    EXPECT_EQ(m.client_count(), 1u);
  }
  // The owner naming an id never given out is told so, on its own nonce.
  protocol::JoinRequest own = leave_request(500, victim + 100);
  own.sender = owner;
  m.inputs().push(std::move(own));
  m.tick(out);
  ASSERT_EQ(out.join_replies.size(), 1u);
  EXPECT_EQ(out.join_replies[0].result, JoinResult::bad_request);
  EXPECT_EQ(m.client_count(), 1u);
}

TEST(MatchJoin, PlayerArchetypeImportanceIsUsedWhenTheTableHasOne) {
  scene::SceneDef s = two_armies(4);
  s.params.inline_json = nlohmann::json::parse(R"({
    "archetypes": {
      "infantry": { "kind": "foot", "weight": 80, "importance": 2 },
      "player": { "character_type": "player", "importance": 6.5 },
      "wall": { "kind": "scenery", "character_type": "prop", "fixed": true },
      "bush": { "kind": "scenery", "character_type": "prop", "fixed": true, "softness": 0.6 }
    },
    "groups": [ { "id": 1 }, { "id": 2 } ]
  })").dump();
  Match m(s, small_config(), "m1");
  Outbox out;
  const protocol::JoinReply reply = test::join_one(m, out, 5);
  EXPECT_DOUBLE_EQ(params_of(m, reply.entity).importance, 6.5);
  m.inputs().push(leave_request(5, reply.client_id));
  m.tick(out);
  EXPECT_DOUBLE_EQ(params_of(m, reply.entity).importance, 2.0);
}

}  // namespace
}  // namespace throng::match
