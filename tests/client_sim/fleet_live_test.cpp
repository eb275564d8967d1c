// Bots against a real throng-server subprocess on loopback: join, move, and agree with the
// server's own summary. Each test uses its own DDS domain (170-199) so parallel runs never meet.
#include <gtest/gtest.h>

#include <cmath>

#include "child_process.h"
#include "fleet_driver.h"
#include "throng/client_sim/fleet.h"
#include "throng/client_sim/report.h"

namespace throng::client_sim {
namespace {

using testing::TempDir;

FleetOptions fleet_options(int domain, const std::string& behavior) {
  FleetOptions o;
  o.domain_id = domain;
  o.behavior = behavior;
  o.seed = 7;
  o.server_wait = std::chrono::seconds(20);
  o.join_timeout = std::chrono::seconds(20);
  return o;
}

TEST(FleetLive, BotsJoinMoveAndAgreeWithTheServer) {
  constexpr int kDomain = 171;
  TempDir dir;
  auto server = testing::start_server(kDomain, dir);
  {
    Fleet fleet(fleet_options(kDomain, "wander,waypoints,charge"));
    ASSERT_TRUE(fleet.connect()) << testing::read_file(dir / "server.log");
    fleet.launch(6);
    ASSERT_TRUE(testing::drive_until(fleet, 20, [&] { return testing::all_active(fleet); }))
        << "not every bot got a snapshot within 20 s";
    testing::drive_for(fleet, 4.0);
    // Stop commanding, but keep receiving snapshots until the server is gone.
    const auto summary = testing::stop_server_and_read_summary(*server, dir);
    ASSERT_TRUE(summary.contains("clients"));

    ASSERT_TRUE(fleet.match());
    EXPECT_EQ(fleet.match()->tick_hz(), 30u);
    EXPECT_TRUE(fleet.last_server_stats().has_value()) << "ServerStats arrive once per second";

    const auto reports = fleet.reports();
    ASSERT_EQ(reports.size(), 6u);
    for (const auto& r : reports) {
      SCOPED_TRACE(r.name);
      EXPECT_EQ(r.state, "joined");
      EXPECT_GT(r.commands.sent, 30u);
      EXPECT_GT(r.latency_ms.size(), 0u);
      EXPECT_EQ(r.decode_errors, 0u);
      EXPECT_GT(r.world_objects, 1u) << "the ClientWorld holds more than the own entity";
      if (r.behavior != "charge") {
        EXPECT_GT(r.moved_m, 1.0) << "the entity moved in the bot's ClientWorld";
      }

      const nlohmann::json* c = testing::find_client(summary, r.name);
      ASSERT_NE(c, nullptr) << "the server's summary lists every bot by name";
      EXPECT_EQ((*c)["client_id"].get<std::uint32_t>(), r.client_id);
      EXPECT_EQ((*c)["entity"].get<std::uint32_t>(), r.entity);
      const auto accepted = (*c)["commands_accepted"].get<std::uint64_t>();
      const auto rejected = (*c)["commands_rejected"].get<std::uint64_t>();
      EXPECT_EQ(accepted + rejected, r.commands.sent) << "every command sent reached the server";
      EXPECT_EQ(rejected, 0u) << "honest bots";
      EXPECT_EQ(r.commands.applied, r.commands.expect_accept) << "every honest command was seen applied";
      const auto published = (*c)["snapshots_published"].get<std::uint64_t>();
      EXPECT_LE(r.snapshots.samples, published);
      EXPECT_GE(static_cast<double>(r.snapshots.samples), 0.9 * static_cast<double>(published));
    }
    const Aggregate a = aggregate(RunReport{30, 4.0, "test", reports, fleet.last_server_stats(), std::nullopt});
    EXPECT_EQ(a.joined, 6u);
    EXPECT_EQ(a.join_failed, 0u);
    // Latency was measured (the figures themselves are reported by throng-bots, not asserted).
    EXPECT_GT(a.latency_ms.p50, 0.0);
    EXPECT_GT(a.kbit_per_s_mean, 1.0);
  }
}

TEST(FleetLive, ParticipantPerClient) {
  constexpr int kDomain = 176;
  TempDir dir;
  auto server = testing::start_server(kDomain, dir);
  auto opts = fleet_options(kDomain, "wander");
  opts.participant_per_client = true;
  Fleet fleet(opts);
  ASSERT_TRUE(fleet.connect()) << testing::read_file(dir / "server.log");
  fleet.launch(3);
  ASSERT_TRUE(testing::drive_until(fleet, 20, [&] { return testing::all_active(fleet); }));
  testing::drive_for(fleet, 2.0);
  const auto reports = fleet.reports();
  for (const auto& r : reports) {
    SCOPED_TRACE(r.name);
    EXPECT_EQ(r.state, "joined");
    EXPECT_GT(r.latency_ms.size(), 0u);
    EXPECT_GT(r.snapshots.samples, 30u);
  }
  // Each participant sees every JoinReply: the fleet counts each client once.
  EXPECT_EQ(fleet.accepted_replies().size(), 3u);
  fleet.leave_all();
  testing::drive_for(fleet, 0.5);
  const auto summary = testing::stop_server_and_read_summary(*server, dir);
  for (const auto& r : reports) {
    const nlohmann::json* c = testing::find_client(summary, r.name);
    ASSERT_NE(c, nullptr);
    EXPECT_EQ((*c)["departure"], "left") << "the leave reached the server";
  }
}

// --rejoin-after: the server is killed and a new one starts on the domain; every bot, its
// snapshots stopped, joins the new server as a new client and plays on; the report counts it.
TEST(FleetLive, BotsJoinANewServerAfterTheirsDied) {
  constexpr int kDomain = 177;
  TempDir first_dir, second_dir;
  auto first = testing::start_server(kDomain, first_dir);
  FleetOptions o = fleet_options(kDomain, "wander");
  o.rejoin_after = std::chrono::milliseconds(1000);
  Fleet fleet(o);
  ASSERT_TRUE(fleet.connect()) << testing::read_file(first_dir / "server.log");
  fleet.launch(3);
  ASSERT_TRUE(testing::drive_until(fleet, 20, [&] { return testing::all_active(fleet); }));
  testing::drive_for(fleet, 0.5);
  std::vector<std::uint32_t> first_ids;
  for (const auto& r : fleet.reports()) first_ids.push_back(r.client_id);
  first->kill_now();
  auto second = testing::start_server(kDomain, second_dir);
  const auto rejoined = [&] {
    for (const auto& r : fleet.reports())
      if (r.rejoins < 1 || r.state != "joined" || r.last_tick == 0) return false;
    return true;
  };
  const bool ok = testing::drive_until(fleet, 30, rejoined);
  std::string states;
  for (const auto& r : fleet.reports())
    states += r.name + ": " + r.state + " rejoins " + std::to_string(r.rejoins) + " client " + std::to_string(r.client_id) +
              " last tick " + std::to_string(r.last_tick) + "\n";
  ASSERT_TRUE(ok) << states << testing::read_file(second_dir / "server.log");
  testing::drive_for(fleet, 1.0);
  const auto summary = testing::stop_server_and_read_summary(*second, second_dir);
  const auto reports = fleet.reports();
  const Aggregate a = aggregate(RunReport{30, 1.0, "test", reports, std::nullopt, std::nullopt});
  EXPECT_GE(a.rejoins, 3u);  // once each; again if a bot's first snapshot from the new server was late
  EXPECT_EQ(a.bots_rejoined, 3u);
  for (const auto& r : reports) {
    SCOPED_TRACE(r.name);
    const nlohmann::json* c = testing::find_client(summary, r.name);
    ASSERT_NE(c, nullptr) << "the new server knows the bot";
    EXPECT_EQ((*c)["client_id"].get<std::uint32_t>(), r.client_id);
    EXPECT_GT((*c)["commands_accepted"].get<std::uint64_t>(), 10u) << "it plays on the new server";
    EXPECT_EQ((*c)["commands_rejected"].get<std::uint64_t>(), 0u) << "its sequences started over";
  }
}

}  // namespace
}  // namespace throng::client_sim
