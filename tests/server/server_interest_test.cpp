// Interest management: a client only receives objects near its camera, and its partition only
// carries its own snapshots.
#include <cmath>

#include <gtest/gtest.h>

#include "server_test_support.h"

namespace throng::test {
namespace {

TEST(ServerInterest, FarObjectsAreNeverSent) {
  auto options = small_server_options(149);
  options.npcs = 2000;
  options.match.interest.radius_m = 15.0;
  options.match.interest.budget_bytes = 0;  // unlimited: everything in view is sent
  ServerThread server(options);
  TestClient client(149);
  const auto r = client.join(3, "watcher");
  ASSERT_TRUE(r && r->result == protocol::JoinResult::accepted);
  // Look at the west army's centre.
  std::uint32_t seq = 0;
  ASSERT_TRUE(client.wait_until([&] { return !client.snapshots().empty(); }));
  const float cam_x = -30.0f, cam_y = 0.0f;
  for (int i = 0; i < 20; ++i) {
    protocol::Command c;
    c.client_id = r->client_id;
    c.entity = r->entity;
    c.sequence = ++seq;
    c.camera_x = cam_x;
    c.camera_y = cam_y;
    c.camera_z = 20.0f;
    client.transport().send_command(c);
    std::this_thread::sleep_for(33ms);
  }
  ASSERT_TRUE(client.wait_until([&] { return client.snapshots().back().last_applied_sequence == seq; }));
  const auto info = client.with_lock([&] { return client.match_infos().back(); });
  std::size_t checked = 0, max_in_one = 0;
  client.with_lock([&] {
    for (const auto& s : client.snapshots()) {
      if (s.last_applied_sequence < 2) continue;  // camera still at the entity before that
      std::vector<protocol::Pose> poses;
      protocol::decode_poses(s, poses);
      max_in_one = std::max(max_in_one, poses.size());
      for (const auto& p : poses) {
        // 15 m plus the exit hysteresis (x1.1) and a tick of motion.
        EXPECT_LE(std::hypot(p.x - cam_x, p.y - cam_y), 15.0 * 1.1 + 0.5) << "object " << p.id << " is far from the camera";
        ++checked;
      }
      EXPECT_LT(s.objects_in_view, info.roster.id.size());
    }
    return 0;
  });
  EXPECT_GT(checked, 100u) << "the camera should see part of an army";
  EXPECT_LT(max_in_one, info.roster.id.size() / 2) << "interest management should cut most of the world";
}

TEST(ServerInterest, EachClientReceivesOnlyItsOwnSnapshots) {
  ServerThread server(small_server_options(150));
  TestClient a(150), b(150);
  const auto ra = a.join(1, "a");
  const auto rb = b.join(2, "b");
  ASSERT_TRUE(ra && ra->result == protocol::JoinResult::accepted);
  ASSERT_TRUE(rb && rb->result == protocol::JoinResult::accepted);
  ASSERT_TRUE(a.wait_until([&] { return a.snapshots().size() >= 10; }));
  ASSERT_TRUE(b.wait_until([&] { return b.snapshots().size() >= 10; }));
  a.with_lock([&] {
    for (const auto& s : a.snapshots()) EXPECT_EQ(s.client_id, ra->client_id);
    return 0;
  });
  b.with_lock([&] {
    for (const auto& s : b.snapshots()) EXPECT_EQ(s.client_id, rb->client_id);
    return 0;
  });
}

}  // namespace
}  // namespace throng::test
