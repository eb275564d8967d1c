// throng-bots as a program: no server, a normal run with --json and Ctrl-C, ramp mode.
#include <gtest/gtest.h>
#include <signal.h>

#include <thread>

#include "child_process.h"

namespace throng::client_sim {
namespace {

using testing::ChildProcess;
using testing::TempDir;

const std::string kBots = THRONG_BIN_DIR "/throng-bots";

TEST(BotsCli, NoServerIsAClearErrorAndNonZeroExit) {
  TempDir dir;
  ChildProcess bots(kBots, {"--clients", "2", "--duration", "5", "--domain", "173", "--server-wait", "1"}, dir / "out",
                    dir / "err");
  const auto code = bots.wait(std::chrono::seconds(20));
  ASSERT_TRUE(code);
  EXPECT_EQ(*code, 2);
  EXPECT_NE(testing::read_file(dir / "err").find("no server on domain 173 within 1 s"), std::string::npos)
      << testing::read_file(dir / "err");
}

TEST(BotsCli, BadUsageIsRefused) {
  TempDir dir;
  ChildProcess bots(kBots, {"--behavior", "moonwalk"}, dir / "out", dir / "err");
  const auto code = bots.wait(std::chrono::seconds(20));
  ASSERT_TRUE(code);
  EXPECT_NE(*code, 0);
  EXPECT_NE(testing::read_file(dir / "err").find("moonwalk"), std::string::npos);
  for (const char* bad : {"nan", "-1", "inf", "4000", "soon"}) {
    ChildProcess b(kBots, {"--rejoin-after", bad}, dir / "out", dir / "err");
    const auto c = b.wait(std::chrono::seconds(20));
    ASSERT_TRUE(c) << bad;
    EXPECT_NE(*c, 0) << bad;
    EXPECT_NE(testing::read_file(dir / "err").find("--rejoin-after"), std::string::npos) << bad;
  }
}

// Over TCP the participants of one process cannot each reach the server (main.cpp says why):
// refused before any participant is made, with the reason and what to do instead.
TEST(BotsCli, ParticipantPerClientOverTcpIsRefusedWithTheReason) {
  TempDir dir;
  ChildProcess bots(kBots, {"--participant-per-client", "--server", "tcp://127.0.0.1:7400", "--server-wait", "1"},
                    dir / "out", dir / "err");
  const auto code = bots.wait(std::chrono::seconds(20));
  ASSERT_TRUE(code);
  EXPECT_EQ(*code, 1);
  const std::string err = testing::read_file(dir / "err");
  EXPECT_NE(err.find("--participant-per-client does not work with --server"), std::string::npos) << err;
  EXPECT_NE(err.find("one throng-bots process per participant"), std::string::npos) << err;
}

TEST(BotsCli, RunsWritesJsonAndLeavesOnSigint) {
  constexpr int kDomain = 174;
  TempDir dir;
  auto server = testing::start_server(kDomain, dir);
  ChildProcess bots(kBots,
                    {"--clients", "4", "--duration", "60", "--domain", std::to_string(kDomain), "--behavior", "mix",
                     "--json", (dir / "bots.json").string(), "--server-wait", "20"},
                    dir / "bots.out", dir / "bots.err");
  // Let them join and play a little, then Ctrl-C.
  std::this_thread::sleep_for(std::chrono::seconds(6));
  ASSERT_TRUE(bots.running()) << testing::read_file(dir / "bots.err");
  bots.signal(SIGINT);
  const auto code = bots.wait(std::chrono::seconds(20));
  ASSERT_TRUE(code) << "throng-bots did not exit after SIGINT";
  EXPECT_EQ(*code, 0) << testing::read_file(dir / "bots.err");

  const std::string out = testing::read_file(dir / "bots.out");
  EXPECT_NE(out.find("cmd->applied"), std::string::npos) << out;
  const std::string err = testing::read_file(dir / "bots.err");
  EXPECT_NE(err.find("clients"), std::string::npos) << "progress lines on stderr";
  const auto j = nlohmann::json::parse(testing::read_file(dir / "bots.json"));
  EXPECT_EQ(j["clients"], 4);
  EXPECT_EQ(j["tick_hz"], 30);
  for (const char* k : {"p50", "p90", "p99", "max"}) EXPECT_TRUE(j["latency_ms"].contains(k)) << k;
  EXPECT_TRUE(j.contains("snapshot_gap_ticks"));
  EXPECT_TRUE(j["kbit_per_s_per_client"].contains("mean"));
  EXPECT_TRUE(j["kbit_per_s_per_client"].contains("max"));
  EXPECT_TRUE(j["join_ms"].contains("p50"));
  EXPECT_TRUE(j["join_ms"].contains("p99"));
  EXPECT_GT(j["commands"]["sent"].get<std::uint64_t>(), 0u);
  EXPECT_GT(j["commands"]["applied"].get<std::uint64_t>(), 0u);
  EXPECT_FALSE(j["server_stats"].is_null());
  ASSERT_EQ(j["per_client"].size(), 4u);

  const auto summary = testing::stop_server_and_read_summary(*server, dir);
  for (const auto& c : j["per_client"]) {
    const nlohmann::json* s = testing::find_client(summary, c["name"].get<std::string>());
    ASSERT_NE(s, nullptr) << c["name"];
    EXPECT_EQ((*s)["departure"], "left") << "leave messages were sent on SIGINT";
  }
}

// The bot fleet authenticates with its identity from a throng-pki directory and plays a match that
// runs with DDS Security. Without credentials the same bots find no server, and the server counts
// and logs the refusal.
TEST(BotsCli, PlayASecureMatchWithTheFleetIdentity) {
  constexpr int kDomain = 179;
  TempDir dir;
  const std::string pki = (dir / "pki").string();
  ASSERT_EQ(std::system((std::string(THRONG_BIN_DIR) + "/throng-pki init " + pki + " >/dev/null 2>&1").c_str()), 0);
  auto server = testing::start_server(kDomain, dir, {"--security", pki});
  ChildProcess bots(kBots,
                    {"--clients", "3", "--duration", "4", "--domain", std::to_string(kDomain), "--security", pki,
                     "--json", (dir / "bots.json").string(), "--server-wait", "20", "--quiet"},
                    dir / "bots.out", dir / "bots.err");
  const auto code = bots.wait(std::chrono::seconds(60));
  ASSERT_TRUE(code);
  EXPECT_EQ(*code, 0) << testing::read_file(dir / "bots.err");
  const auto j = nlohmann::json::parse(testing::read_file(dir / "bots.json"));
  EXPECT_EQ(j["joined"], 3);
  EXPECT_GT(j["commands"]["applied"].get<std::uint64_t>(), 0u);

  ChildProcess anonymous(kBots, {"--clients", "1", "--duration", "2", "--domain", std::to_string(kDomain), "--server-wait", "3"},
                         dir / "anon.out", dir / "anon.err");
  const auto anon_code = anonymous.wait(std::chrono::seconds(30));
  ASSERT_TRUE(anon_code);
  EXPECT_EQ(*anon_code, 2) << "a participant without credentials found the secure server";

  const auto summary = testing::stop_server_and_read_summary(*server, dir);
  EXPECT_EQ(summary["clients"].size(), 3u);
  EXPECT_GE(summary["participants_refused"].get<std::uint64_t>(), 1u) << "the anonymous bots were not counted";
  const std::string log = testing::read_file(dir / "server.log");
  EXPECT_NE(log.find("DDS Security refused"), std::string::npos) << log;
}

TEST(BotsCli, MissingCredentialsAreAClearError) {
  TempDir dir;
  ChildProcess bots(kBots, {"--clients", "1", "--domain", "180", "--security", dir.path().string()}, dir / "out", dir / "err");
  const auto code = bots.wait(std::chrono::seconds(20));
  ASSERT_TRUE(code);
  EXPECT_EQ(*code, 1);
  EXPECT_NE(testing::read_file(dir / "err").find("throng-pki init"), std::string::npos) << testing::read_file(dir / "err");
}

TEST(BotsCli, RampReportsSteps) {
  constexpr int kDomain = 175;
  TempDir dir;
  auto server = testing::start_server(kDomain, dir);
  ChildProcess bots(kBots,
                    {"--ramp", "--ramp-start", "2", "--ramp-step", "2", "--ramp-max", "4", "--ramp-step-s", "2.5",
                     "--ramp-settle-s", "0.5", "--domain", std::to_string(kDomain), "--json",
                     (dir / "ramp.json").string(), "--server-wait", "20", "--quiet"},
                    dir / "out", dir / "err");
  const auto code = bots.wait(std::chrono::seconds(90));
  ASSERT_TRUE(code) << "ramp did not finish";
  EXPECT_EQ(*code, 0) << testing::read_file(dir / "err");
  const auto j = nlohmann::json::parse(testing::read_file(dir / "ramp.json"));
  ASSERT_TRUE(j.contains("ramp"));
  const auto& ramp = j["ramp"];
  ASSERT_GE(ramp["steps"].size(), 1u);
  EXPECT_EQ(ramp["steps"][0]["clients"], 2);
  for (const auto& s : ramp["steps"]) {
    EXPECT_TRUE(s["server_stats_seen"].get<bool>()) << s.dump();
    EXPECT_GT(s["ticks"].get<std::uint64_t>(), 0u);
  }
  const auto best = ramp["max_sustained_clients"].get<std::uint32_t>();
  EXPECT_TRUE(best == 0 || best == 2 || best == 4) << best;
  EXPECT_FALSE(ramp["stopped_because"].get<std::string>().empty());
  EXPECT_NE(testing::read_file(dir / "out").find("largest sustained"), std::string::npos);
  testing::stop_server_and_read_summary(*server, dir);
}

}  // namespace
}  // namespace throng::client_sim
