// The Bot without DDS: join handshake, snapshots into its world, commands and latency.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <vector>

#include "throng/client_sim/bot.h"
#include "throng/protocol/codec.h"

namespace throng::client_sim {
namespace {

using std::chrono::milliseconds;

protocol::JoinReply accepted(std::uint64_t nonce) {
  protocol::JoinReply r;
  r.client_nonce = nonce;
  r.result = protocol::JoinResult::accepted;
  r.client_id = 4;
  r.entity = 1001;
  r.snapshot_partition = "c4";
  r.faction = 1;
  return r;
}

protocol::Snapshot own_snapshot(std::uint64_t tick, std::uint32_t applied, float x) {
  protocol::Snapshot s;
  s.client_id = 4;
  s.tick = tick;
  s.last_applied_sequence = applied;
  s.entity = 1001;
  s.entity_x = x;
  s.entity_y = 2.0f;
  const std::vector<protocol::Pose> poses{{5, 1, 1, 0, 0}};
  EXPECT_TRUE(protocol::encode_poses(poses, 0, 0, 1, s));
  return s;
}

TEST(Bot, JoinsSendsCommandsAndMeasures) {
  const TimePoint t0{};
  BotConfig cfg;
  cfg.name = "b";
  cfg.behavior = "idle";
  cfg.nonce = 1234;
  cfg.seed = 9;
  Bot bot(cfg, t0);
  const auto req = bot.join_request(t0 + milliseconds(1));
  EXPECT_EQ(req.client_nonce, 1234u);
  EXPECT_FALSE(req.leave);
  EXPECT_EQ(bot.state(), Bot::State::joining);

  auto other = accepted(999);
  EXPECT_FALSE(bot.on_join_reply(other)) << "someone else's reply";
  EXPECT_TRUE(bot.on_join_reply(accepted(1234)));
  EXPECT_FALSE(bot.on_join_reply(accepted(1234))) << "a repeated reply is not a second join";
  EXPECT_EQ(bot.state(), Bot::State::joined);
  EXPECT_EQ(bot.client_id(), 4u);
  EXPECT_EQ(bot.partition(), "c4");

  // No commands before the bot has seen its own entity (its camera would be unknown).
  std::vector<protocol::Command> out;
  bot.tick(t0 + milliseconds(10), {}, out);
  EXPECT_TRUE(out.empty());

  bot.on_snapshot(own_snapshot(50, 0, 3.0f), 120, t0 + milliseconds(40));
  bot.tick(t0 + milliseconds(50), {}, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].client_id, 4u);
  EXPECT_EQ(out[0].entity, 1001u);
  EXPECT_EQ(out[0].sequence, 1u);
  EXPECT_EQ(out[0].last_seen_tick, 50u);
  EXPECT_FLOAT_EQ(out[0].camera_x, 3.0f);
  EXPECT_FLOAT_EQ(out[0].camera_y, 2.0f);
  bot.tick(t0 + milliseconds(83), {}, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].sequence, 2u);

  bot.on_snapshot(own_snapshot(51, 1, 3.5f), 120, t0 + milliseconds(75));
  bot.on_snapshot(own_snapshot(53, 2, 4.0f), 120, t0 + milliseconds(140));  // tick 52 missed
  // A snapshot for another client id is ignored.
  auto foreign = own_snapshot(54, 2, 9.0f);
  foreign.client_id = 5;
  bot.on_snapshot(foreign, 120, t0 + milliseconds(150));

  const BotReport r = bot.report(t0 + milliseconds(1040));
  EXPECT_EQ(r.state, "joined");
  EXPECT_EQ(r.commands.sent, 2u);
  EXPECT_EQ(r.commands.applied, 2u);
  ASSERT_EQ(r.latency_ms.size(), 2u);
  EXPECT_NEAR(r.latency_ms.values()[0], 25.0, 1e-6);
  EXPECT_NEAR(r.latency_ms.values()[1], 57.0, 1e-6);
  EXPECT_EQ(r.snapshots.samples, 3u);
  EXPECT_EQ(r.snapshots.bytes, 360u);
  EXPECT_EQ(r.snapshots.missed_ticks, 1u);
  ASSERT_TRUE(r.join_ms);
  EXPECT_NEAR(*r.join_ms, 40.0, 1e-6);
  EXPECT_NEAR(r.active_s, 1.0, 1e-9);
  EXPECT_NEAR(r.kbit_per_s(), 360 * 8 / 1000.0, 1e-9);
  EXPECT_NEAR(r.moved_m, 1.0, 1e-6);
  EXPECT_EQ(r.last_applied_sequence, 2u);
  EXPECT_EQ(r.world_objects, 2u);  // object 5 and the own entity

  const auto leave = bot.leave_request();
  ASSERT_TRUE(leave);
  EXPECT_TRUE(leave->leave);
  EXPECT_EQ(leave->client_id, 4u);
  EXPECT_FALSE(bot.leave_request()) << "only once";
}

// Its server gone for longer than the limit, a joined bot joins again as a new client: a new
// nonce, its world, sequences and pending commands reset, the rejoin counted; the stall shows in
// its snapshot inter-arrival, not as missed ticks of the new client.
TEST(Bot, JoinsAgainAsANewClientAfterItsSnapshotsStop) {
  const TimePoint t0{};
  BotConfig cfg;
  cfg.name = "b";
  cfg.behavior = "idle";
  cfg.nonce = 1234;
  cfg.seed = 9;
  Bot bot(cfg, t0);
  (void)bot.join_request(t0);
  ASSERT_TRUE(bot.on_join_reply(accepted(1234), t0 + milliseconds(20)));
  bot.on_snapshot(own_snapshot(50, 0, 3.0f), 120, t0 + milliseconds(40));
  std::vector<protocol::Command> out;
  bot.tick(t0 + milliseconds(50), {}, out);
  ASSERT_EQ(out.size(), 1u);

  EXPECT_FALSE(bot.begin_rejoin(t0 + milliseconds(900), milliseconds(1000))) << "not silent long enough";
  const auto old = bot.begin_rejoin(t0 + milliseconds(1100), milliseconds(1000));
  ASSERT_TRUE(old);
  EXPECT_EQ(*old, 4u);
  EXPECT_EQ(bot.rejoins(), 1u);
  EXPECT_EQ(bot.state(), Bot::State::created);
  EXPECT_NE(bot.nonce(), 1234u);
  EXPECT_FALSE(bot.begin_rejoin(t0 + milliseconds(5000), milliseconds(1000))) << "only a joined bot rejoins";

  const auto req = bot.join_request(t0 + milliseconds(1100));
  EXPECT_EQ(req.client_nonce, bot.nonce());
  protocol::JoinReply again = accepted(bot.nonce());
  again.client_id = 9;
  again.entity = 2002;
  again.snapshot_partition = "c9";
  ASSERT_TRUE(bot.on_join_reply(again, t0 + milliseconds(1250)));
  EXPECT_FALSE(bot.begin_rejoin(t0 + milliseconds(2000), milliseconds(1000)))
      << "silence counts from the new client's acceptance, not from the old snapshots";
  EXPECT_EQ(bot.client_id(), 9u);
  // The new server's ticks start low again; they are not "out of order" against the old ones.
  protocol::Snapshot s = own_snapshot(3, 0, 7.0f);
  s.client_id = 9;
  s.entity = 2002;
  bot.on_snapshot(s, 100, t0 + milliseconds(1300));
  out.clear();
  bot.tick(t0 + milliseconds(1310), {}, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].client_id, 9u);
  EXPECT_EQ(out[0].entity, 2002u);
  EXPECT_EQ(out[0].sequence, 1u) << "a new client's sequences start at 1";

  const BotReport r = bot.report(t0 + milliseconds(1400));
  EXPECT_EQ(r.rejoins, 1u);
  EXPECT_EQ(r.snapshots.out_of_order, 0u);
  EXPECT_EQ(r.snapshots.samples, 2u);
  EXPECT_NEAR(r.interarrival_ms.summary().max, 1260.0, 1e-6) << "the outage, first snapshot to the next";
  EXPECT_EQ(r.commands.sent, 2u);
  EXPECT_EQ(r.commands.applied, 0u) << "the first client's command was never seen applied; it is forgotten";
}

TEST(Bot, RefusedAndTimedOut) {
  const TimePoint t0{};
  BotConfig cfg;
  cfg.name = "r";
  cfg.behavior = "wander";
  Bot refused(cfg, t0);
  EXPECT_NE(refused.nonce(), 0u) << "a random nonce is drawn";
  refused.join_request(t0);
  auto reply = accepted(refused.nonce());
  reply.result = protocol::JoinResult::match_full;
  reply.reason = "full";
  EXPECT_FALSE(refused.on_join_reply(reply));
  EXPECT_EQ(refused.state(), Bot::State::refused);
  EXPECT_EQ(refused.report(t0).refused_reason, "full");
  EXPECT_FALSE(refused.leave_request());

  Bot late(cfg, t0);
  late.join_request(t0);
  late.mark_timed_out();
  EXPECT_EQ(late.state(), Bot::State::timed_out);
  EXPECT_FALSE(late.on_join_reply(accepted(late.nonce())));

  cfg.behavior = "moonwalk";
  EXPECT_THROW(Bot(cfg, t0), std::invalid_argument);
}

}  // namespace
}  // namespace throng::client_sim
