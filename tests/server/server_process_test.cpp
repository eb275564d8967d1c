// throng-server as a process: graceful shutdown on SIGTERM (exit 0, summary written, clients told
// the match ended), the admin endpoint serving throng_ metrics, and bad command lines rejected.
#include <cmath>
#include <cstdlib>
#include <csignal>
#include <regex>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sstream>

#include "server_test_support.h"
#include "support/child_process.h"

namespace throng::test {
namespace {

const std::string kServer = std::string(THRONG_BIN_DIR) + "/throng-server";

TEST(ServerProcess, SigtermEndsTheMatchGracefully) {
  TempDir dir("throng-sigterm");
  const auto summary = (dir / "summary.json").string();
  ChildProcess server(kServer,
                      {"--scene", "battle", "--npcs", "300", "--domain", "151", "--admin-port", "-1", "--summary-json",
                       summary, "--log-level", "info", "--log", (dir / "match.tlog").string(), "--trim-memory-every",
                       "0.2"},
                      dir / "out.txt", dir / "err.txt");
  TestClient client(151);
  const auto r = client.join(12, "witness");
  ASSERT_TRUE(r && r->result == protocol::JoinResult::accepted) << read_file(dir / "err.txt");
  // Past tick 60, so the log holds a world keyframe (one every 60 ticks at 30 Hz).
  ASSERT_TRUE(client.wait_until([&] { return client.snapshots().size() >= 75; }, 15s));
  server.signal(SIGTERM);
  EXPECT_EQ(server.wait(10s), 0) << read_file(dir / "err.txt");
  // Clients are told the match ended.
  EXPECT_TRUE(client.wait_until([&] {
    return !client.match_infos().empty() && client.match_infos().back().state == protocol::MatchState::ended;
  }, 5s));
  // The summary is complete JSON and the log says what happened.
  const auto j = nlohmann::json::parse(read_file(summary));
  EXPECT_GT(j["ticks"].get<std::uint64_t>(), 5u);
  EXPECT_EQ(j["clients"].size(), 1u);
  const auto err = read_file(dir / "err.txt");
  EXPECT_NE(err.find("SIGTERM received"), std::string::npos) << err;
  EXPECT_NE(read_file(dir / "out.txt").find("throng-server summary"), std::string::npos);
  // The memory trimmer ran every 0.2 s while the match did (75 snapshots at 30 Hz: 2.5 s at least).
  std::smatch trims;
  ASSERT_TRUE(std::regex_search(err, trims, std::regex("memory trims: ([0-9]+) \\(every 0.2 s\\)"))) << err;
  EXPECT_GE(std::stoi(trims[1].str()), 5) << err;
  // The match log it wrote replays bit-exactly: every tick's state hash matches.
  ChildProcess replay(std::string(THRONG_BIN_DIR) + "/throng-replay", {"verify", (dir / "match.tlog").string()},
                      dir / "verify.txt", dir / "verify.err");
  EXPECT_EQ(replay.wait(60s), 0) << read_file(dir / "verify.txt") << read_file(dir / "verify.err");
  EXPECT_NE(read_file(dir / "verify.txt").find("all state hashes and keyframes match"), std::string::npos)
      << read_file(dir / "verify.txt");
  EXPECT_NE(err.find("match log keyframes: "), std::string::npos) << err;  // count, bytes, save/append times
  // And a seek through that keyframe lands on the logged state.
  ChildProcess seek(std::string(THRONG_BIN_DIR) + "/throng-replay", {"seek", (dir / "match.tlog").string(), "--tick", "65"},
                    dir / "seek.txt", dir / "seek.err");
  EXPECT_EQ(seek.wait(60s), 0) << read_file(dir / "seek.txt") << read_file(dir / "seek.err");
  EXPECT_NE(read_file(dir / "seek.txt").find("from the keyframe of tick 60"), std::string::npos) << read_file(dir / "seek.txt");
  // By default the keyframes leave the snapshot baselines out, and the header says so.
  ChildProcess info(std::string(THRONG_BIN_DIR) + "/throng-replay", {"info", (dir / "match.tlog").string(), "--json"},
                    dir / "info.json", dir / "info.err");
  ASSERT_EQ(info.wait(30s), 0) << read_file(dir / "info.err");
  const auto ij = nlohmann::json::parse(read_file(dir / "info.json"));
  EXPECT_FALSE(ij.at("keyframe_snapshot_baselines").get<bool>()) << ij.dump();
  EXPECT_GE(ij.at("keyframes").get<int>(), 1) << ij.dump();
}

// --log-format json: every stderr line is one JSON object naming the match (log collectors index
// them); the text format names it too. The match log lands in --log-dir under the match id.
TEST(ServerProcess, EveryLogLineNamesTheMatchInJsonOrText) {
  TempDir dir("throng-logfmt");
  for (const std::string format : {"json", "text"}) {
    ChildProcess server(kServer,
                        {"--duration", "0.5", "--npcs", "300", "--admin-port", "-1", "--domain", "159", "--log-format",
                         format, "--log-dir", (dir / format).string(), "--summary-json", (dir / "s.json").string()},
                        dir / "out.txt", dir / "err.txt");
    ASSERT_EQ(server.wait(20s), 0) << read_file(dir / "err.txt");
    const std::string id = nlohmann::json::parse(read_file(dir / "s.json"))["match_id"];
    std::istringstream lines(read_file(dir / "err.txt"));
    int count = 0;
    for (std::string line; std::getline(lines, line); ++count) {
      if (format == "json") {
        const auto j = nlohmann::json::parse(line);  // throws (fails the test) on a line that is not JSON
        EXPECT_EQ(j["match"], id) << line;
        EXPECT_FALSE(j["msg"].get<std::string>().empty()) << line;
        EXPECT_TRUE(j.contains("time") && j.contains("level")) << line;
      } else {
        EXPECT_NE(line.find("[" + id + "]"), std::string::npos) << line;
      }
    }
    EXPECT_GE(count, 3) << format;
    EXPECT_TRUE(std::filesystem::exists(dir / format / (id + ".tlog"))) << "no match log in --log-dir";
  }
}

// The value of the sample `series` (name plus labels, exactly as exposed) in a text exposition;
// fails the test and returns NaN when it is missing.
double metric_value(const std::string& exposition, const std::string& series) {
  const std::size_t at = exposition.find("\n" + series + " ");
  if (at == std::string::npos) {
    ADD_FAILURE() << series << " missing from /metrics";
    return std::nan("");
  }
  return std::stod(exposition.substr(at + 1 + series.size() + 1));
}

TEST(ServerProcess, AdminEndpointServesHealthReadinessAndMetrics) {
  auto o = small_server_options(152);
  o.admin_port = 0;
  ServerThread server(o);
  TestClient client(152);
  const auto r = client.join(1, "scraper");
  ASSERT_TRUE(r && r->result == protocol::JoinResult::accepted);
  ASSERT_TRUE(client.wait_until([&] { return client.snapshots().size() >= 3; }));
  const auto port = server.server().admin_port();
  ASSERT_NE(port, 0);
  EXPECT_NE(http_get(port, "/healthz").find("200 OK"), std::string::npos);
  EXPECT_NE(http_get(port, "/readyz").find("200 OK"), std::string::npos);
  const auto metrics = http_get(port, "/metrics");
  for (const char* name : {"throng_ticks_total", "throng_tick_duration_seconds_bucket", "throng_tick_overruns_total",
                           "throng_clients 1", "throng_commands_rejected_total{reason=\"non_finite\"}",
                           "throng_snapshot_bytes_total", "throng_push_events_total"})
    EXPECT_NE(metrics.find(name), std::string::npos) << name << " missing from /metrics";
  // The world's step figures: every phase timed once per tick, and the first tick (no kept pair
  // list yet) searched. The scrape reads the counters one by one while the tick runs, so a tick
  // may land between two of them.
  const double ticks = metric_value(metrics, "throng_ticks_total");
  const double searches = metric_value(metrics, "throng_world_pair_searches_total");
  EXPECT_GE(ticks, 3);
  EXPECT_GE(searches, 1);
  EXPECT_LE(searches, ticks + 1);
  for (const char* phase : {"move", "params", "search", "solve"}) {
    const double timed = metric_value(metrics, std::string("throng_world_phase_seconds_count{phase=\"") + phase + "\"}");
    EXPECT_NEAR(timed, ticks, 2) << phase;
  }
  EXPECT_GT(metric_value(metrics, "throng_world_candidate_pairs"), 0) << "a battle of hundreds has pairs";
  EXPECT_GE(metric_value(metrics, "throng_world_second_searches_total"), 0);
  // The Grafana dashboard in deploy/ charts only series the server exports (a renamed metric must
  // not leave an empty panel behind).
  const std::string dashboard = read_file(std::filesystem::path(THRONG_SOURCE_DIR) / "deploy/grafana/throng-dashboard.json");
  const std::regex series("throng_[a-z_]+");
  int charted = 0;
  for (auto it = std::sregex_iterator(dashboard.begin(), dashboard.end(), series); it != std::sregex_iterator(); ++it) {
    std::string name = it->str();
    if (name == "throng_matches") continue;  // the dashboard's own uid
    ++charted;
    EXPECT_NE(metrics.find("\n" + name), std::string::npos) << name << " is charted but not in /metrics";
  }
  EXPECT_GE(charted, 10);
}

TEST(ServerProcess, BadCommandLinesAreRejectedWithAClearMessage) {
  TempDir dir("throng-cli");
  struct Case {
    std::vector<std::string> args;
    std::string expect;
  };
  const std::vector<Case> cases = {
      {{"--tick-hz", "0"}, "--tick-hz"},
      {{"--domain", "400"}, "--domain"},
      {{"--domain", "232"}, "--domain"},  // Fast DDS would end the process computing its ports
      {{"--duration", "nan"}, "--duration"},
      {{"--client-timeout", "inf"}, "--client-timeout"},
      {{"--end-when-empty", "nan"}, "--end-when-empty"},
      {{"--end-when-empty", "-1"}, "--end-when-empty"},
      {{"--end-when-routed", "inf"}, "--end-when-routed"},
      {{"--trim-memory-every", "nan"}, "--trim-memory-every"},
      {{"--trim-memory-every", "-1"}, "--trim-memory-every"},
      {{"--trim-memory-every", "0.05"}, "at least 0.1 s"},
      {{"--log-keyframe-ticks", "-1"}, "--log-keyframe-ticks"},
      {{"--log-keyframe-ticks", "200000"}, "--log-keyframe-ticks"},
      {{"--solver-threads", "0"}, "--solver-threads"},
      {{"--solver-threads", "65"}, "--solver-threads"},
      {{"--listen", "tcp://0.0.0.0"}, "host and port are both needed"},
      {{"--listen", "http://0.0.0.0:7400"}, "must start with tcp:// or udp://"},
      {{"--listen", "udp://0.0.0.0:7400"}, "needs the address players reach it at (--public-address)"},
      {{"--public-address", "10.0.0.1"}, "needs --listen"},
      {{"--standby", "--listen", "tcp://0.0.0.0:7400"}, "does not run over --listen"},
      {{"--listen", "tcp://127.0.0.1:7400"}, "listen on 0.0.0.0"},
      {{"--scene", "/no/such/scene.json"}, "neither a built-in scene"},
      {{"--bogus"}, "bogus"},
      {{"--security", "/no/such/pki"}, "--security"},
      {{"--security", dir.path().string()}, "throng-pki init"},  // a directory without the files
  };
  for (const auto& c : cases) {
    std::vector<std::string> args = c.args;
    args.insert(args.end(), {"--no-log", "--admin-port", "-1"});
    if (c.args[0] != "--domain") args.insert(args.end(), {"--domain", "153"});
    ChildProcess server(kServer, args, dir / "out.txt", dir / "err.txt");
    const auto code = server.wait(20s);
    ASSERT_TRUE(code.has_value()) << c.args[0] << ": still running after 20 s";
    EXPECT_NE(*code, 0) << c.args[0];
    const auto err = read_file(dir / "err.txt");
    EXPECT_NE(err.find(c.expect), std::string::npos) << "for " << c.args[0] << " got: " << err;
  }
  // Under Agones the sidecar port comes from the environment: a bad one is an error, not a guess.
  ::setenv("AGONES_SDK_HTTP_PORT", "70000", 1);
  ChildProcess agones(kServer, {"--no-log", "--admin-port", "-1", "--domain", "153"}, dir / "out.txt", dir / "err.txt");
  const auto agones_code = agones.wait(20s);
  ::unsetenv("AGONES_SDK_HTTP_PORT");
  ASSERT_TRUE(agones_code.has_value());
  EXPECT_NE(*agones_code, 0);
  EXPECT_NE(read_file(dir / "err.txt").find("AGONES_SDK_HTTP_PORT must be a port number"), std::string::npos)
      << read_file(dir / "err.txt");
  ChildProcess help(kServer, {"--help"}, dir / "help.txt", dir / "help.err");
  EXPECT_EQ(help.wait(10s), 0);
  EXPECT_NE(read_file(dir / "help.txt").find("--interest-radius"), std::string::npos);
}

}  // namespace
}  // namespace throng::test
