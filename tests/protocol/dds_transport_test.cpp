// ServerTransport <-> ClientTransport on loopback: joins, replies, match info for late joiners,
// commands and operator parameter changes, each with every field checked. Each test has its own
// DDS domain (110..139) so parallel ctest runs never cross.
#include "throng/protocol/dds_transport.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include "message_equality.h"
#include "transport_test_util.h"

namespace throng::protocol {
namespace {

using test::expect_same;
using test::Inbox;
using test::kWait;
using test::loopback;

JoinReply reply_for(std::uint64_t nonce, std::uint32_t client_id) {
  JoinReply r;
  r.client_nonce = nonce;
  r.result = client_id % 2 ? JoinResult::accepted : JoinResult::match_full;
  r.reason = client_id % 2 ? "" : "match is full (" + std::to_string(client_id) + ")";
  r.client_id = client_id;
  r.entity = 1000 + client_id;
  r.snapshot_partition = "c" + std::to_string(client_id);
  r.tick = 5'000'000'000ull + client_id;
  r.faction = static_cast<std::uint8_t>(client_id % 3);
  return r;
}

MatchInfo small_match_info(std::uint32_t param_version) {
  MatchInfo m;
  m.match_id = "match-7f3a";
  m.scene_name = "bridge_charge";
  m.tick_hz = 30;
  m.start_tick = 12;
  m.param_table_hash = 0x0123'4567'89AB'CDEFull;
  m.push_policy_hash = 0xFEDC'BA98'7654'3210ull;
  m.param_version = param_version;
  m.max_clients = 64;
  m.interest_radius_m = 25.5f;
  m.world_min_x = -100.25f;
  m.world_min_y = -50.5f;
  m.world_max_x = 100.75f;
  m.world_max_y = 50.125f;
  m.state = MatchState::running;
  m.archetypes = {"infantry", "horse", "bush"};
  SceneryShape box;
  box.id = 1;
  box.kind = ShapeKind::box;
  box.archetype = "wall";
  box.cx = 1.5f, box.cy = 2.5f, box.cz = 0.5f, box.hx = 3, box.hy = 0.25f, box.hz = 1, box.yaw_rad = 0.75f;
  SceneryShape bush;
  bush.id = 2;
  bush.kind = ShapeKind::cylinder;
  bush.archetype = "bush";
  bush.softness = 0.6f;
  bush.cx = -4, bush.cy = 8, bush.radius = 1.25f, bush.half_height = 0.5f;
  SceneryShape ramp;
  ramp.id = 3;
  ramp.kind = ShapeKind::mesh;
  ramp.archetype = "ramp";
  ramp.vertices = {0, 0, 0, 4, 0, 0, 4, 2, 1};
  ramp.triangles = {0, 1, 2};
  m.scenery = {box, bush, ramp};
  m.roster.id = {11, 12, 13};
  m.roster.radius_mm = {300, 300, 700};
  m.roster.half_height_mm = {600, 600, 0};
  m.roster.faction = {0, 1, 1};
  m.roster.character_type = {1, 1, 2};
  m.roster.archetype = {0, 0, 1};
  return m;
}

ServerStats stats_at(std::uint64_t tick) {
  ServerStats s;
  s.tick = tick;
  s.tick_hz = 30;
  s.clients = 3;
  s.bodies = 2500;
  s.tick_ms_p50 = 4.25f, s.tick_ms_p99 = 9.5f, s.tick_ms_max = 12.75f;
  s.overruns = 1;
  s.commands_accepted = 9000, s.commands_rejected = 7;
  s.snapshot_bytes = 123456789, s.snapshot_samples = 4242;
  s.push_events = 77, s.state_hash = 0xABCD'EF01'2345'6789ull;
  s.state = MatchState::ended;
  return s;
}

TEST(DdsTransport, JoinRequestsReachTheServerInOrder) {
  Inbox<JoinRequest> joins;
  ServerTransport server(loopback(111, "server"));
  server.start({.on_join = [&](JoinRequest&& r) { joins.push(std::move(r)); }, .on_command = {}, .on_param_update = {}, .on_standby_request = {}, .on_primary_claim = {}});
  ClientTransport client(loopback(111, "client"));
  client.start({});

  const auto before = std::chrono::steady_clock::now();
  ASSERT_TRUE(client.wait_for_server(kWait));
  const auto discovery_ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - before).count();
  ::testing::Test::RecordProperty("discovery_ms", static_cast<int>(discovery_ms));
  std::printf("loopback discovery (wait_for_server): %lld ms\n", static_cast<long long>(discovery_ms));

  JoinRequest join;
  join.client_nonce = 0xDEAD'BEEF'CAFE'F00Dull;
  join.protocol_version = kProtocolVersion;
  join.name = "bot-0001 \xE2\x9A\x94";  // UTF-8 survives
  JoinRequest leave;
  leave.client_nonce = 0x1234'5678'9ABC'DEF0ull;
  leave.protocol_version = 99;
  leave.name = "bot-0002";
  leave.leave = true;
  leave.client_id = 4'000'000'000u;
  client.send_join(join);
  client.send_join(leave);

  ASSERT_TRUE(joins.wait_for_count(2));
  const auto got = joins.items();
  ASSERT_EQ(got.size(), 2u);
  expect_same(got[0], join);
  expect_same(got[1], leave);
}

TEST(DdsTransport, LateJoinersGetMatchInfoJoinRepliesAndStatsFromHistory) {
  ServerTransport server(loopback(112, "server"));
  server.start({});
  // Everything is published before any client exists: only transient-local history delivers it.
  // 12 replies > Fast DDS's default of 10 instances, and the reply of nonce 105 is replaced.
  constexpr int kReplies = 12;
  for (int i = 0; i < kReplies; ++i) server.publish_join_reply(reply_for(100 + i, 1 + i));
  JoinReply replaced = reply_for(105, 40);
  server.publish_join_reply(replaced);
  server.publish_match_info(small_match_info(1));
  server.publish_match_info(small_match_info(2));  // keep last 1: only this one is history
  server.publish_stats(stats_at(900));
  server.publish_stats(stats_at(930));

  for (const char* name : {"early-client", "later-client"}) {
    SCOPED_TRACE(name);
    Inbox<MatchInfo> infos;
    Inbox<JoinReply> replies;
    Inbox<ServerStats> stats;
    ClientTransport client(loopback(112, name));
    client.start({.on_match_info = [&](MatchInfo&& m) { infos.push(std::move(m)); },
                  .on_join_reply = [&](JoinReply&& r) { replies.push(std::move(r)); },
                  .on_param_reply = {},
                  .on_stats = [&](ServerStats&& s) { stats.push(std::move(s)); }});
    ASSERT_TRUE(infos.wait_for_count(1));
    ASSERT_TRUE(replies.wait_for_count(kReplies));
    ASSERT_TRUE(stats.wait_for_count(1));

    expect_same(infos.items().front(), small_match_info(2));
    expect_same(stats.items().front(), stats_at(930));
    std::vector<JoinReply> got = replies.items();
    ASSERT_EQ(got.size(), static_cast<std::size_t>(kReplies));
    std::sort(got.begin(), got.end(), [](const JoinReply& a, const JoinReply& b) { return a.client_nonce < b.client_nonce; });
    for (int i = 0; i < kReplies; ++i) expect_same(got[i], i == 5 ? replaced : reply_for(100 + i, 1 + i));
  }
  const TransportCounters c = server.counters();
  EXPECT_EQ(c.other_samples, static_cast<std::uint64_t>(kReplies + 1 + 2 + 2));
  EXPECT_EQ(c.snapshot_samples, 0u);
}

TEST(DdsTransport, CommandArrivesWithEveryFieldIntact) {
  Inbox<Command> commands;
  ServerTransport server(loopback(113, "server"));
  server.start({.on_join = {}, .on_command = [&](Command&& c) { commands.push(std::move(c)); }, .on_param_update = {}, .on_standby_request = {}, .on_primary_claim = {}});
  ClientTransport client(loopback(113, "client"));
  client.start({});
  ASSERT_TRUE(client.wait_for_server(kWait));

  Command cmd;
  cmd.client_id = 42;
  cmd.entity = 0x8000'0123u;
  cmd.sequence = 17;
  cmd.last_seen_tick = (1ull << 40) + 7;
  cmd.move_x = 0.625f;
  cmd.move_y = -0.75f;
  cmd.facing_rad = -3.0f;
  cmd.actions = kActionSprint | kActionBrace | (1u << 31);  // unknown bit travels; the server rejects it
  cmd.camera_x = 1234.5f;
  cmd.camera_y = -0.001f;
  cmd.camera_z = 18.0f;
  ASSERT_TRUE(test::send_until([&] { client.send_command(cmd); },
                               [&](std::chrono::milliseconds t) { return commands.wait_for_count(1, t); }));
  for (const Command& got : commands.items()) expect_same(got, cmd);
}

// A reader keeps an instance for every key it has seen until the key's writer releases it or goes
// away: a client that leaves releases its command instance, and the server's reader forgets it
// (one per client session, for the whole match, otherwise).
TEST(DdsTransport, AReleasedClientsCommandInstanceIsForgottenByTheServer) {
  Inbox<Command> commands;
  ServerTransport server(loopback(138, "server"));
  server.start({.on_join = {}, .on_command = [&](Command&& c) { commands.push(std::move(c)); }, .on_param_update = {}, .on_standby_request = {}, .on_primary_claim = {}});
  ClientTransport client(loopback(138, "client"));
  client.start({});
  ASSERT_TRUE(client.wait_for_server(kWait));
  Command a, b;
  a.client_id = 42;
  b.client_id = 43;
  ASSERT_TRUE(test::send_until([&] { client.send_command(a); client.send_command(b); },
                               [&](std::chrono::milliseconds t) {
                                 return commands.wait_for_count(2, t) && server.holds_command_instance(42) &&
                                        server.holds_command_instance(43);
                               }));
  EXPECT_FALSE(server.holds_command_instance(44));
  EXPECT_FALSE(client.release_commands(44)) << "never written: nothing to release";

  ASSERT_TRUE(client.release_commands(42));
  const auto deadline = std::chrono::steady_clock::now() + kWait;
  while (server.holds_command_instance(42) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_FALSE(server.holds_command_instance(42)) << "the released client's instance is still held";
  EXPECT_TRUE(server.holds_command_instance(43)) << "the other client's instance must stay";
  // Released, the client id can still be written again (a new instance).
  const std::size_t before = commands.items().size();
  ASSERT_TRUE(test::send_until([&] { client.send_command(a); },
                               [&](std::chrono::milliseconds t) { return commands.wait_for_count(before + 1, t); }));
}

TEST(DdsTransport, ParamUpdateAndReplyRoundTrip) {
  Inbox<ParamUpdate> updates;
  Inbox<ParamReply> replies;
  ServerTransport server(loopback(114, "server"));
  server.start({.on_join = {}, .on_command = {}, .on_param_update = [&](ParamUpdate&& u) {
                  // What the real server does in its input queue, done here on the listener thread.
                  ParamReply r;
                  r.request_id = u.request_id;
                  r.ok = u.policy_json.empty();
                  r.error = r.ok ? "" : "policy rejected: " + u.policy_json.substr(0, 8);
                  r.param_version = 3;
                  r.tick = 777;
                  server.publish_param_reply(r);
                  updates.push(std::move(u));
                }, .on_standby_request = {}, .on_primary_claim = {}});
  ClientTransport op(loopback(114, "operator"));
  op.start({.on_match_info = {}, .on_join_reply = {}, .on_param_reply = [&](ParamReply&& r) { replies.push(std::move(r)); },
            .on_stats = {}});
  ASSERT_TRUE(op.wait_for_server(kWait));

  ParamUpdate weight;
  weight.request_id = 9'000'000'001ull;
  weight.entity = 11;
  weight.param = "weight";
  weight.value = 82.125;
  ParamUpdate policy;
  policy.request_id = 9'000'000'002ull;
  policy.policy_json = R"({"mode": "nonsense"})";
  op.send_param_update(weight);
  op.send_param_update(policy);

  ASSERT_TRUE(updates.wait_for_count(2));
  ASSERT_TRUE(replies.wait_for_count(2));
  expect_same(updates.items()[0], weight);
  expect_same(updates.items()[1], policy);
  ParamReply ok{.request_id = weight.request_id, .ok = true, .error = "", .param_version = 3, .tick = 777};
  ParamReply refused{.request_id = policy.request_id, .ok = false, .error = "policy rejected: {\"mode\":", .param_version = 3, .tick = 777};
  expect_same(replies.items()[0], ok);
  expect_same(replies.items()[1], refused);
}

TEST(DdsTransport, WaitForServerTimesOutWhenNoServerRuns) {
  ClientTransport client(loopback(119, "lonely-client"));
  client.start({});
  const auto before = std::chrono::steady_clock::now();
  EXPECT_FALSE(client.wait_for_server(std::chrono::milliseconds(300)));
  EXPECT_GE(std::chrono::steady_clock::now() - before, std::chrono::milliseconds(300));
}

// Fast DDS 2.9.1 would number a process's participants from a counter that never goes down, and
// discovery on loopback tries only ids 0..119: two participants made after 125 others (a standby
// that takes over in a long-lived process, a test binary) would never find each other.
TEST(DdsTransport, ParticipantsMadeAfterManyOthersInOneProcessStillDiscoverEachOther) {
  for (int i = 0; i < 125; ++i) ClientTransport churn(loopback(123, "churn-" + std::to_string(i)));
  ServerTransport server(loopback(123, "late-server"));
  server.start({});
  ClientTransport client(loopback(123, "late-client"));
  client.start({});
  EXPECT_TRUE(client.wait_for_server(kWait));
}

TEST(DdsTransport, NetworkModeUsesFastDdsDefaultTransports) {
  TransportOptions network = loopback(121, "network-server");
  network.loopback_only = false;
  ServerTransport server(network);
  server.start({});
  server.publish_stats(stats_at(1));
  EXPECT_EQ(server.counters().other_samples, 1u);
}

TEST(DdsTransport, ErrorsNameWhatFailed) {
  try {
    ServerTransport bad(loopback(300, "server"));
    FAIL() << "domain 300 accepted";
  } catch (const TransportError& e) {
    EXPECT_EQ(std::string(e.what()), "cannot create participant 'server' on domain 300: domain id must be 0..231");
  }
  EXPECT_THROW(ClientTransport(loopback(-1, "client")), TransportError);

  ServerTransport server(loopback(120, "server"));
  EXPECT_THROW(server.open_client_channel(1, ""), TransportError);
  EXPECT_THROW(server.open_client_channel(1, "c*"), TransportError);
  server.start({});
  EXPECT_THROW(server.start({}), TransportError);
  ClientTransport client(loopback(120, "client"));
  EXPECT_THROW(client.subscribe_snapshots(1, "", {}), TransportError);
  client.start({});
  EXPECT_THROW(client.start({}), TransportError);
}

}  // namespace
}  // namespace throng::protocol
