// Gateway (transport-free game side): join, commands and sequence numbers, camera, stale page
// input, latency, and the JSON the page gets.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "throng/protocol/codec.h"
#include "throng/protocol/contacts.h"
#include "throng/view/gateway.h"

namespace throng::view {
namespace {

using namespace std::chrono_literals;

constexpr std::uint64_t kNonce = 77;

protocol::JoinReply accepted() {
  protocol::JoinReply r;
  r.client_nonce = kNonce;
  r.result = protocol::JoinResult::accepted;
  r.client_id = 5;
  r.entity = 42;
  r.snapshot_partition = "c5";
  r.faction = 2;
  return r;
}

protocol::MatchInfo match_info() {
  protocol::MatchInfo m;
  m.match_id = "m1";
  m.scene_name = "battle";
  m.tick_hz = 30;
  m.interest_radius_m = 30;
  m.world_min_x = -50;
  m.world_min_y = -20;
  m.world_max_x = 50;
  m.world_max_y = 20;
  m.archetypes = {"infantry", "cavalry"};
  protocol::SceneryShape box;
  box.id = 900;
  box.kind = protocol::ShapeKind::box;
  box.archetype = "wall";
  box.cx = 1;
  box.hx = 2;
  box.hy = 0.5f;
  box.yaw_rad = 0.3f;
  protocol::SceneryShape bush;
  bush.id = 901;
  bush.kind = protocol::ShapeKind::cylinder;
  bush.archetype = "bush";
  bush.softness = 0.6f;
  bush.radius = 1.5f;
  protocol::SceneryShape mesh;
  mesh.id = 902;
  mesh.kind = protocol::ShapeKind::mesh;
  mesh.vertices = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  mesh.triangles = {0, 1, 2, 0, 1, 7};  // the second triangle is out of range: dropped
  m.scenery = {box, bush, mesh};
  m.roster.id = {42, 43};
  m.roster.radius_mm = {350, 900};
  m.roster.half_height_mm = {550, 800};
  m.roster.faction = {2, 1};
  m.roster.character_type = {0, 2};
  m.roster.archetype = {0, 1};
  return m;
}

protocol::Snapshot snapshot(std::uint64_t tick, std::uint32_t applied_seq, double own_x) {
  protocol::Snapshot s;
  s.client_id = 5;
  s.tick = tick;
  s.last_applied_sequence = applied_seq;
  s.entity = 42;
  s.entity_x = static_cast<float>(own_x);
  s.entity_y = 1.0f;
  s.entity_yaw = 0.5f;
  s.objects_in_view = 2;
  const protocol::Pose poses[] = {{42, own_x, 1.0, 0.0, 0.5}, {43, 3.0, -2.0, 0.0, 1.0}};
  EXPECT_TRUE(protocol::encode_poses(poses, 0, 0, 1, s));
  return s;
}

struct Joined {
  Gateway g;
  TimePoint t0 = Clock::now();
  Joined() : g(GatewayOptions{"test-view", kNonce, 500ms, 1024, {}}) {
    const auto req = g.join_request(t0);
    EXPECT_EQ(req.client_nonce, kNonce);
    EXPECT_EQ(req.name, "test-view");
    EXPECT_TRUE(g.on_join_reply(accepted()));
    g.on_match_info(match_info());
  }
};

TEST(Gateway, JoinsOnlyWithItsOwnNonce) {
  Gateway g(GatewayOptions{"v", kNonce, 500ms, 1024, {}});
  g.join_request(Clock::now());
  auto other = accepted();
  other.client_nonce = 78;
  EXPECT_FALSE(g.on_join_reply(other));
  EXPECT_EQ(g.state(), Gateway::State::joining);
  EXPECT_TRUE(g.on_join_reply(accepted()));
  EXPECT_FALSE(g.on_join_reply(accepted())) << "a repeated reply is not a new acceptance";
  const auto leave = g.leave_request();
  ASSERT_TRUE(leave);
  EXPECT_TRUE(leave->leave);
  EXPECT_EQ(leave->client_id, 5u);
  EXPECT_FALSE(g.leave_request());
}

TEST(Gateway, RefusalIsReported) {
  Gateway g(GatewayOptions{"v", kNonce, 500ms, 1024, {}});
  g.join_request(Clock::now());
  auto r = accepted();
  r.result = protocol::JoinResult::match_full;
  EXPECT_FALSE(g.on_join_reply(r));
  EXPECT_EQ(g.state(), Gateway::State::refused);
}

TEST(Gateway, CommandsStartWithTheOwnEntityAndOwnTheSequence) {
  Joined j;
  EXPECT_FALSE(j.g.make_command(j.t0, std::nullopt, std::nullopt)) << "no command before the own entity is seen";
  ASSERT_TRUE(j.g.on_snapshot(snapshot(10, 0, 4.0), 100, j.t0));
  PageInput in;
  in.move_x = 1;
  in.facing_rad = 0.25f;
  in.actions = protocol::kActionSprint;
  for (std::uint32_t seq = 1; seq <= 3; ++seq) {
    const auto c = j.g.make_command(j.t0 + 10ms, in, j.t0);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->sequence, seq);
    EXPECT_EQ(c->client_id, 5u);
    EXPECT_EQ(c->entity, 42u);
    EXPECT_EQ(c->last_seen_tick, 10u);
    EXPECT_EQ(c->move_x, 1.0f);
    EXPECT_EQ(c->facing_rad, 0.25f);
    EXPECT_EQ(c->actions, protocol::kActionSprint);
    EXPECT_FLOAT_EQ(c->camera_x, 4.0f) << "the camera follows the entity";
    EXPECT_FLOAT_EQ(c->camera_y, 1.0f);
  }
}

TEST(Gateway, PannedCameraAndStaleInput) {
  Joined j;
  ASSERT_TRUE(j.g.on_snapshot(snapshot(10, 0, 4.0), 100, j.t0));
  PageInput in;
  in.move_y = -1;
  in.camera_x = 20;
  in.camera_y = -3;
  auto c = j.g.make_command(j.t0 + 100ms, in, j.t0);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->camera_x, 20.0f);
  EXPECT_EQ(c->camera_y, -3.0f);
  EXPECT_EQ(c->move_y, -1.0f);
  // The page went quiet for longer than the input timeout: stand still, follow, keep facing.
  c = j.g.make_command(j.t0 + 600ms, in, j.t0);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->move_x, 0.0f);
  EXPECT_EQ(c->move_y, 0.0f);
  EXPECT_EQ(c->actions, 0u);
  EXPECT_NEAR(c->facing_rad, 0.5f, 1e-6);
  EXPECT_FLOAT_EQ(c->camera_x, 4.0f);
}

TEST(Gateway, LatencyIsSendToFirstSnapshotThatAppliedIt) {
  Joined j;
  ASSERT_TRUE(j.g.on_snapshot(snapshot(10, 0, 4.0), 100, j.t0));
  EXPECT_FALSE(j.g.latency_ms(j.t0));
  ASSERT_TRUE(j.g.make_command(j.t0, std::nullopt, std::nullopt));         // seq 1 at t0
  ASSERT_TRUE(j.g.make_command(j.t0 + 33ms, std::nullopt, std::nullopt));  // seq 2
  ASSERT_TRUE(j.g.on_snapshot(snapshot(11, 0, 4.0), 100, j.t0 + 40ms));    // applies nothing
  ASSERT_TRUE(j.g.on_snapshot(snapshot(12, 2, 4.0), 100, j.t0 + 73ms));    // applies 1 and 2
  const auto lat = j.g.latency_ms(j.t0 + 80ms);
  ASSERT_TRUE(lat);
  EXPECT_NEAR(*lat, 73.0, 0.5) << "median of {73, 40}";  // upper median of two samples
  EXPECT_EQ(j.g.last_applied_sequence(), 2u);
  EXPECT_GT(j.g.kbit_per_s(j.t0 + 80ms), 0.0);
  EXPECT_FALSE(j.g.latency_ms(j.t0 + 2s)) << "a one-second window";
  EXPECT_EQ(j.g.kbit_per_s(j.t0 + 2s), 0.0);
}

TEST(Gateway, StaleAndForeignSnapshotsAreNotApplied) {
  Joined j;
  ASSERT_TRUE(j.g.on_snapshot(snapshot(10, 0, 4.0), 100, j.t0));
  EXPECT_FALSE(j.g.on_snapshot(snapshot(10, 0, 5.0), 100, j.t0)) << "same tick";
  auto foreign = snapshot(11, 0, 5.0);
  foreign.client_id = 6;
  EXPECT_FALSE(j.g.on_snapshot(foreign, 100, j.t0));
  EXPECT_EQ(j.g.snapshots_applied(), 1u);
}

TEST(Gateway, MatchJson) {
  Joined j;
  const auto m = nlohmann::json::parse(j.g.match_json());
  EXPECT_EQ(m["type"], "match");
  EXPECT_EQ(m["scene"], "battle");
  EXPECT_EQ(m["tick_hz"], 30);
  EXPECT_EQ(m["bounds"], nlohmann::json({-50.0, -20.0, 50.0, 20.0}));
  ASSERT_EQ(m["scenery"].size(), 3u);
  EXPECT_EQ(m["scenery"][0]["kind"], "box");
  EXPECT_DOUBLE_EQ(m["scenery"][0]["yaw"].get<double>(), 0.3);
  EXPECT_EQ(m["scenery"][1]["kind"], "cylinder");
  EXPECT_DOUBLE_EQ(m["scenery"][1]["softness"].get<double>(), 0.6);
  EXPECT_EQ(m["scenery"][2]["kind"], "mesh");
  EXPECT_EQ(m["scenery"][2]["triangles"].size(), 3u);
  EXPECT_EQ(m["roster"]["id"], nlohmann::json({42, 43}));
  EXPECT_EQ(m["roster"]["radius"], nlohmann::json({0.35, 0.9}));
  EXPECT_EQ(m["roster"]["half_height"], nlohmann::json({0.55, 0.8}));
  EXPECT_EQ(m["roster"]["faction"], nlohmann::json({2, 1}));
  EXPECT_EQ(m["archetypes"], nlohmann::json({"infantry", "cavalry"}));
  EXPECT_EQ(m["character_types"][2], "mount");
}

TEST(Gateway, FrameJson) {
  Joined j;
  ASSERT_TRUE(j.g.on_snapshot(snapshot(10, 0, 4.0), 100, j.t0));
  ASSERT_TRUE(j.g.on_snapshot(snapshot(11, 0, 4.5), 100, j.t0 + 33ms));
  FrameExtras extras;
  extras.pages = 1;
  extras.input_errors[static_cast<std::size_t>(InputError::not_json)] = 3;
  const auto f = nlohmann::json::parse(j.g.frame_json(j.t0 + 40ms, extras));
  EXPECT_EQ(f["type"], "frame");
  EXPECT_EQ(f["tick"], 11);
  EXPECT_EQ(f["entity"], 42);
  EXPECT_EQ(f["faction"], 2);
  EXPECT_DOUBLE_EQ(f["self"]["x"].get<double>(), 4.5) << "own pose: the newest, unquantized";
  ASSERT_EQ(f["objects"].size(), 8u) << "id, x, y, yaw per object";
  EXPECT_EQ(f["objects"][0], 42);
  EXPECT_EQ(f["objects"][4], 43);
  EXPECT_NEAR(f["objects"][5].get<double>(), 3.0, 1e-3);
  EXPECT_EQ(f["in_view"], 2);
  EXPECT_EQ(f["tracked"], 2);
  EXPECT_TRUE(f["latency_ms"].is_null());
  EXPECT_EQ(f["input_errors"]["not_json"], 3);
  EXPECT_EQ(f["input_errors_total"], 3);
  EXPECT_EQ(f["pages"], 1);
  EXPECT_EQ(f["ended"], false);
}

protocol::ContactPairs contacts(std::uint32_t client, std::uint64_t tick) {
  protocol::ContactPairs c;
  c.client_id = client;
  c.tick = tick;
  c.pairs_near = 3;
  c.camera_x = 4.0f;
  c.camera_y = 1.0f;
  c.radius_m = 12.0f;
  protocol::push_contact(c, 42, 43, 0.7, 0.012, 0.0105);
  protocol::push_contact(c, 43, 44, 0.25, 0.001, 0.0008);
  return c;
}

// The contacts overlay: frames carry the newest valid pairs while the page asks for them.
TEST(Gateway, ContactsReachTheFrameOnlyWhileThePageAsks) {
  Joined j;
  ASSERT_TRUE(j.g.on_snapshot(snapshot(10, 0, 4.0), 100, j.t0));
  PageInput in;
  in.actions = protocol::kActionContacts;
  const auto c1 = j.g.make_command(j.t0, in, j.t0);
  ASSERT_TRUE(c1);
  EXPECT_EQ(c1->actions, protocol::kActionContacts) << "the page's request travels in the command";

  EXPECT_TRUE(j.g.on_contacts(contacts(5, 10), 84, j.t0));
  EXPECT_FALSE(j.g.on_contacts(contacts(6, 10), 84, j.t0)) << "another client's pairs";
  protocol::ContactPairs broken = contacts(5, 11);
  broken.share_a.pop_back();
  EXPECT_FALSE(j.g.on_contacts(broken, 80, j.t0)) << "arrays of different lengths";
  EXPECT_FALSE(j.g.on_contacts(contacts(5, 9), 84, j.t0)) << "older than the newest";
  EXPECT_EQ(j.g.contacts_rejected(), 2u);
  EXPECT_EQ(j.g.contacts_received(), 1u);

  auto f = nlohmann::json::parse(j.g.frame_json(j.t0 + 10ms, FrameExtras{}));
  ASSERT_TRUE(f["contacts"].is_object()) << f.dump();
  EXPECT_EQ(f["contacts"]["tick"], 10);
  EXPECT_EQ(f["contacts"]["near"], 3);
  const auto& p = f["contacts"]["pairs"];
  ASSERT_EQ(p.size(), 10u) << "a, b, share_a, depth mm, push mm per pair";
  EXPECT_EQ(p[0], 42);
  EXPECT_EQ(p[1], 43);
  EXPECT_NEAR(p[2].get<double>(), 0.7, 1e-4);
  EXPECT_NEAR(p[3].get<double>(), 12.0, 0.05);
  EXPECT_NEAR(p[7].get<double>(), 0.25, 1e-4);
  EXPECT_GT(f["contacts_kbps"].get<double>(), 0.0);

  // The page stops asking: the next command says so, and frames carry no pairs.
  const auto c2 = j.g.make_command(j.t0 + 33ms, PageInput{}, j.t0 + 33ms);
  ASSERT_TRUE(c2);
  EXPECT_EQ(c2->actions, 0u);
  f = nlohmann::json::parse(j.g.frame_json(j.t0 + 40ms, FrameExtras{}));
  EXPECT_TRUE(f["contacts"].is_null());
}

}  // namespace
}  // namespace throng::view
