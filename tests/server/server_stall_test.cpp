// The server process is stopped for 2 s (SIGSTOP, then SIGCONT: a preempted VM, a debugger, a
// swap storm) while a client plays: the tick catches up as documented (at most 3 ticks back to
// back, the rest of the lost time given up and counted as skipped), the client keeps its
// client_id, entity and sequence, its commands are applied again at once, and nobody has to
// rejoin. What is lost: the 2 s of match time the server did not run.
#include <csignal>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <thread>

#include "server_test_support.h"
#include "support/child_process.h"

namespace throng::test {
namespace {

using namespace std::chrono_literals;

const std::string kServer = std::string(THRONG_BIN_DIR) + "/throng-server";

TEST(ServerStall, StoppedForTwoSecondsTheServerCatchesUpAndTheClientPlaysOn) {
  TempDir dir("throng-stall");
  const auto summary = dir / "summary.json";
  ChildProcess server(kServer,
                      {"--scene", "battle", "--npcs", "300", "--domain", "196", "--admin-port", "-1", "--duration", "8",
                       "--summary-json", summary.string(), "--no-log", "--log-level", "info"},
                      dir / "out.txt", dir / "err.txt");
  TestClient client(196);
  const auto reply = client.join(5, "stalled");
  ASSERT_TRUE(reply && reply->result == protocol::JoinResult::accepted) << read_file(dir / "err.txt");
  std::uint32_t seq = 0;
  auto command = [&] {
    protocol::Command c;
    c.client_id = reply->client_id;
    c.entity = reply->entity;
    c.sequence = ++seq;
    c.move_x = 1.0f;
    client.transport().send_command(c);
  };
  for (int i = 0; i < 20; ++i, std::this_thread::sleep_for(33ms)) command();
  ASSERT_TRUE(client.wait_until([&] { return client.snapshots().back().last_applied_sequence >= seq - 2; }));
  const std::uint32_t before_tick = client.with_lock([&] { return client.snapshots().back().tick; });

  server.signal(SIGSTOP);
  std::this_thread::sleep_for(2s);
  const std::size_t snapshots_while_stopped = client.with_lock([&] { return client.snapshots().size(); });
  server.signal(SIGCONT);

  // The same client, entity and command stream carry on: the next commands are applied within a
  // second, without a new join.
  for (int i = 0; i < 20; ++i, std::this_thread::sleep_for(33ms)) command();
  ASSERT_TRUE(client.wait_until([&] { return client.snapshots().back().last_applied_sequence >= seq - 2; }, 5s))
      << "commands were not applied after the stall";
  const auto after = client.with_lock([&] { return client.snapshots().back(); });
  EXPECT_EQ(after.entity, reply->entity);
  EXPECT_GT(client.with_lock([&] { return client.snapshots().size(); }), snapshots_while_stopped + 10);
  // Ticks resumed where they stopped: the 2 s were given up, not replayed (about 60 ticks at 30 Hz).
  EXPECT_LT(after.tick, before_tick + 30 + 3 + 40);

  ASSERT_EQ(server.wait(30s), 0) << read_file(dir / "err.txt");
  const auto j = nlohmann::json::parse(read_file(summary));
  EXPECT_GE(j["skipped_ticks"].get<std::uint64_t>(), 45u) << "the stall's ticks were not counted as skipped";
  EXPECT_EQ(j["clients"].size(), 1u) << "the client joined more than once";
  EXPECT_EQ(client.with_lock([&] { return client.replies().size(); }), 1u);
}

}  // namespace
}  // namespace throng::test
