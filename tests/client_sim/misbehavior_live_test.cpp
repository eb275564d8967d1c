// Every misbehaviour is rejected by the server for the right reason and changes nothing: the
// NPCs barely move (--npc-speed 0.001: 1 mm/s), so an entity only moves if a command moved it.
//  - nan joins first; hijack then commands nan's entity (the first other client), so nan's entity
//    standing still also shows that no hijack command was applied.
// (An honest mover is left out on purpose: it could bump the standing bots. FleetLive shows that
// applied commands move entities.)
#include <gtest/gtest.h>

#include <map>

#include "child_process.h"
#include "fleet_driver.h"
#include "throng/client_sim/fleet.h"

namespace throng::client_sim {
namespace {

using testing::TempDir;

TEST(MisbehaviorLive, RejectedForTheRightReasonAndChangeNothing) {
  constexpr int kDomain = 172;
  TempDir dir;
  auto server = testing::start_server(kDomain, dir, {"--npc-speed", "0.001"});
  FleetOptions o;
  o.domain_id = kDomain;
  o.seed = 11;
  o.server_wait = std::chrono::seconds(20);
  o.join_timeout = std::chrono::seconds(20);
  Fleet fleet(o);
  ASSERT_TRUE(fleet.connect()) << testing::read_file(dir / "server.log");

  const std::size_t nan = fleet.launch(1, "nan").front();
  ASSERT_TRUE(testing::drive_until(fleet, 20, [&] { return testing::all_active(fleet); }));
  const auto others = fleet.launch(4, "hijack,flood,stale,idle");
  ASSERT_TRUE(testing::drive_until(fleet, 20, [&] { return testing::all_active(fleet); }));
  testing::drive_for(fleet, 4.0);
  const auto summary = testing::stop_server_and_read_summary(*server, dir);
  ASSERT_TRUE(summary.contains("rejected_by_reason")) << summary.dump(2);
  const auto& reasons = summary["rejected_by_reason"];

  std::map<std::string, BotReport> by_behavior;
  for (const auto& r : fleet.reports()) by_behavior[r.behavior] = r;
  ASSERT_EQ(by_behavior.size(), 5u);
  EXPECT_EQ(fleet.bot(nan).behavior(), "nan");
  EXPECT_EQ(by_behavior["hijack"].name, fleet.bot(others[0]).name());

  auto server_counts = [&](const BotReport& r) {
    const nlohmann::json* c = testing::find_client(summary, r.name);
    EXPECT_NE(c, nullptr) << r.name;
    if (!c) return std::pair<std::uint64_t, std::uint64_t>{0, 0};
    return std::pair{(*c)["commands_accepted"].get<std::uint64_t>(), (*c)["commands_rejected"].get<std::uint64_t>()};
  };

  for (const auto& [behavior, r] : by_behavior) {
    SCOPED_TRACE(behavior);
    EXPECT_EQ(r.state, "joined");
    EXPECT_GT(r.commands.sent, 30u);
    const auto [accepted, rejected] = server_counts(r);
    if (behavior == "flood") {
      // 20 best-effort commands at once: the command reader keeps the last 16 per client, so a
      // slow moment on a loaded machine may drop a few before the server sees them.
      EXPECT_LE(accepted + rejected, r.commands.sent);
      EXPECT_GE(static_cast<double>(accepted + rejected), 0.9 * static_cast<double>(r.commands.sent));
    } else {
      EXPECT_EQ(accepted + rejected, r.commands.sent);
    }
    ASSERT_TRUE(r.first_pose && r.last_pose);
    EXPECT_LT(r.moved_m, 0.2) << "nothing moved this entity";
  }

  {
    const BotReport& r = by_behavior["nan"];
    EXPECT_EQ(server_counts(r).first, 0u);
    EXPECT_GE(reasons["non_finite"].get<std::uint64_t>(), r.commands.sent);
    EXPECT_EQ(r.commands.applied, 0u);
  }
  {
    const BotReport& r = by_behavior["hijack"];
    EXPECT_EQ(server_counts(r).first, 0u);
    EXPECT_GE(reasons["not_your_entity"].get<std::uint64_t>(), r.commands.sent);
  }
  {
    const BotReport& r = by_behavior["flood"];
    const auto [accepted, rejected] = server_counts(r);
    EXPECT_EQ(r.commands.sent % 20, 0u);
    EXPECT_GT(rejected, r.commands.sent / 2) << "most of a 20-per-tick flood is refused";
    EXPECT_EQ(reasons["rate_limited"].get<std::uint64_t>(), rejected) << "all of them rate_limited";
    EXPECT_LE(accepted, 4 * summary["ticks"].get<std::uint64_t>()) << "at most max_commands_per_tick (4) per tick";
    EXPECT_GT(accepted, 0u) << "the first commands of a tick are honest and accepted";
  }
  {
    const BotReport& r = by_behavior["stale"];
    const auto [accepted, rejected] = server_counts(r);
    EXPECT_LE(accepted, 15u) << "only the honest standing-still commands";
    EXPECT_GT(accepted, 0u);
    EXPECT_EQ(r.commands.expect_reject, rejected);
    EXPECT_EQ(reasons["stale_sequence"].get<std::uint64_t>() + reasons["duplicate_sequence"].get<std::uint64_t>(),
              rejected);
    EXPECT_GT(reasons["duplicate_sequence"].get<std::uint64_t>(), 0u) << "the newest sequence replayed";
  }
  {
    const BotReport& r = by_behavior["idle"];
    EXPECT_EQ(server_counts(r).second, 0u);
  }
  EXPECT_EQ(reasons["unknown_client"].get<std::uint64_t>(), 0u);
}

}  // namespace
}  // namespace throng::client_sim
