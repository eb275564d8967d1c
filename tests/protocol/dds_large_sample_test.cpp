// A match info with a roster of 10,000 movables (~110 kB, far over one 64 kB UDP datagram) must
// arrive intact: reliable, fragmented, sent asynchronously; and a late joiner gets it from history.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "message_equality.h"
#include "throng/protocol/dds_transport.h"
#include "transport_test_util.h"

namespace throng::protocol {
namespace {

using test::Inbox;
using test::loopback;

MatchInfo crowd_match_info(std::size_t movables) {
  MatchInfo m;
  m.match_id = "large-roster";
  m.scene_name = "ten_thousand";
  m.max_clients = 1000;
  m.param_version = 5;
  m.archetypes = {"infantry", "pike", "horse", "giant"};
  for (std::uint32_t i = 0; i < movables; ++i) {
    m.roster.id.push_back(1 + i * 3);
    m.roster.radius_mm.push_back(static_cast<std::uint16_t>(250 + i % 500));
    m.roster.half_height_mm.push_back(static_cast<std::uint16_t>(i % 7 == 0 ? 0 : 600 + i % 300));
    m.roster.faction.push_back(static_cast<std::uint8_t>(i % 4));
    m.roster.character_type.push_back(static_cast<std::uint8_t>(i % 3));
    m.roster.archetype.push_back(static_cast<std::uint8_t>(i % 4));
  }
  for (std::uint32_t s = 0; s < 20; ++s) {
    SceneryShape rock;
    rock.id = 100000 + s;
    rock.kind = ShapeKind::mesh;
    rock.archetype = "rock-" + std::to_string(s);
    for (int v = 0; v < 90; ++v) rock.vertices.push_back(static_cast<float>(s * 100 + v) * 0.25f);
    for (std::uint32_t t = 0; t < 30; ++t) rock.triangles.push_back(t % 30);
    m.scenery.push_back(rock);
  }
  return m;
}

TEST(DdsLargeSample, RosterOfTenThousandArrivesIntactLiveAndFromHistory) {
  const MatchInfo big = crowd_match_info(10'000);
  ServerTransport server(loopback(118, "server"));
  server.start({});

  // Live: the client is already there when the sample is written.
  Inbox<MatchInfo> live_infos;
  ClientTransport live(loopback(118, "live-client"));
  live.start({.on_match_info = [&](MatchInfo&& m) { live_infos.push(std::move(m)); }, .on_join_reply = {},
              .on_param_reply = {}, .on_stats = {}});
  ASSERT_TRUE(live.wait_for_server(test::kWait));
  const auto sent = std::chrono::steady_clock::now();
  server.publish_match_info(big);
  ASSERT_TRUE(live_infos.wait_for_count(1));
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - sent).count();
  const std::uint64_t bytes = server.counters().other_bytes;
  std::printf("match info with %zu movables: %llu bytes serialized, delivered in %lld ms\n", big.roster.id.size(),
              static_cast<unsigned long long>(bytes), static_cast<long long>(ms));
  ::testing::Test::RecordProperty("match_info_10000_bytes", static_cast<int>(bytes));
  EXPECT_GT(bytes, 64u * 1024u) << "the test must exercise fragmentation";
  test::expect_same(live_infos.items().front(), big);

  // Late: transient-local history hands the same large sample to a newcomer.
  Inbox<MatchInfo> late_infos;
  ClientTransport late(loopback(118, "late-client"));
  late.start({.on_match_info = [&](MatchInfo&& m) { late_infos.push(std::move(m)); }, .on_join_reply = {},
              .on_param_reply = {}, .on_stats = {}});
  ASSERT_TRUE(late_infos.wait_for_count(1));
  test::expect_same(late_infos.items().front(), big);
}

}  // namespace
}  // namespace throng::protocol
