// throng-bots against a playing log: every bot is accepted as a spectator, receives snapshots it
// can decode and builds a world from them; the player counts (and ignores) their commands.
#include <csignal>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "play_test_support.h"

namespace throng::play_test {
namespace {

TEST(PlayBots, ThrongBotsWatchAPlayingLog) {
  constexpr int kDomain = 211;
  test::TempDir dir("throng-play-bots");
  const auto log = dir / "match.tlog";
  record_log(log, 300);
  auto player = start_player(log, kDomain, {"--loop"}, dir);

  const auto report = dir / "bots.json";
  test::ChildProcess bots(kBots,
                          {"--clients", "3", "--duration", "4", "--domain", std::to_string(kDomain), "--behavior", "wander",
                           "--json", report.string(), "--server-wait", "20", "--join-timeout", "20", "-q"},
                          dir / "bots.out", dir / "bots.err");
  const auto code = bots.wait(60s);
  ASSERT_TRUE(code.has_value()) << "throng-bots did not finish";
  EXPECT_EQ(*code, 0) << test::read_file(dir / "bots.err") << test::read_file(dir / "play.err");

  const auto j = nlohmann::json::parse(test::read_file(report));
  EXPECT_EQ(j["joined"], 3);
  EXPECT_EQ(j["join_failed"], 0);
  EXPECT_EQ(j["tick_hz"], 30);
  ASSERT_EQ(j["per_client"].size(), 3u);
  std::set<std::uint32_t> ids;
  for (const auto& c : j["per_client"]) {
    SCOPED_TRACE(c["name"].get<std::string>());
    EXPECT_EQ(c["state"], "joined");
    EXPECT_GT(c["client_id"].get<std::uint32_t>(), 1'000'000'000u);
    ids.insert(c["client_id"].get<std::uint32_t>());
    EXPECT_GT(c["snapshots"]["received"].get<std::uint64_t>(), 30u);
    EXPECT_EQ(c["snapshots"]["decode_errors"], 0);
    EXPECT_GT(c["world_objects"].get<std::uint64_t>(), 10u) << "the bot's world was built from the replay's snapshots";
    EXPECT_EQ(c["commands"]["applied"], 0) << "a replay applies nothing a watcher sends";
  }
  EXPECT_EQ(ids.size(), 3u) << "each bot has a channel of its own";

  player->signal(SIGTERM);
  EXPECT_EQ(player->wait(20s), 0) << test::read_file(dir / "play.err");
  const std::string out = test::read_file(dir / "play.out");
  EXPECT_NE(out.find("watchers: 3 joined, 0 refused, 3 left"), std::string::npos) << out;
  EXPECT_EQ(out.find(" 0 commands ignored"), std::string::npos) << out;
}

// A replay played with DDS Security: the bot fleet watches it with its identity, each watcher in a
// partition named after the fleet's certificate (the only ones its permissions let it read).
TEST(PlayBots, SecureReplayIsWatchedWithTheFleetIdentity) {
  constexpr int kDomain = 217;
  test::TempDir dir("throng-play-secure");
  const auto log = dir / "match.tlog";
  record_log(log, 300);
  const std::string pki = (dir / "pki").string();
  ASSERT_EQ(std::system((std::string(THRONG_BIN_DIR) + "/throng-pki init " + pki + " >/dev/null 2>&1").c_str()), 0);
  auto player = start_player(log, kDomain, {"--loop", "--security", pki}, dir);
  const auto report = dir / "bots.json";
  test::ChildProcess bots(kBots,
                          {"--clients", "2", "--duration", "3", "--domain", std::to_string(kDomain), "--security", pki,
                           "--json", report.string(), "--server-wait", "20", "--join-timeout", "20", "-q"},
                          dir / "bots.out", dir / "bots.err");
  const auto code = bots.wait(60s);
  ASSERT_TRUE(code.has_value()) << "throng-bots did not finish";
  EXPECT_EQ(*code, 0) << test::read_file(dir / "bots.err") << test::read_file(dir / "play.err");
  const auto j = nlohmann::json::parse(test::read_file(report));
  EXPECT_EQ(j["joined"], 2);
  for (const auto& c : j["per_client"]) EXPECT_GT(c["snapshots"]["received"].get<std::uint64_t>(), 10u) << c.dump();
  player->signal(SIGTERM);
  EXPECT_EQ(player->wait(20s), 0) << test::read_file(dir / "play.err");
}

}  // namespace
}  // namespace throng::play_test
