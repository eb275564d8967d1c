// throng-server as a process: graceful shutdown on SIGTERM (exit 0, summary written, clients told
// the match ended), the admin endpoint serving throng_ metrics, and bad command lines rejected.
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "server_test_support.h"

extern char** environ;

namespace throng::test {
namespace {

// Runs a binary with args; returns its pid.
pid_t spawn(const std::vector<std::string>& argv, const std::string& out_file) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, (out_file + ".err").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0].c_str(), &fa, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  return rc == 0 ? pid : -1;
}

// waitpid with a deadline; returns the exit status or -1 (and kills the child) on timeout.
int wait_exit(pid_t pid, std::chrono::milliseconds timeout) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < until) {
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    std::this_thread::sleep_for(20ms);
  }
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  return -1;
}

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

std::filesystem::path temp_dir(const std::string& name) {
  auto d = std::filesystem::temp_directory_path() / ("throng-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::create_directories(d);
  return d;
}

const std::string kServer = std::string(THRONG_BIN_DIR) + "/throng-server";

TEST(ServerProcess, SigtermEndsTheMatchGracefully) {
  const auto dir = temp_dir("sigterm");
  const auto summary = (dir / "summary.json").string();
  const pid_t pid = spawn({kServer, "--scene", "battle", "--npcs", "300", "--domain", "151", "--admin-port", "-1",
                           "--summary-json", summary, "--log-level", "info", "--log", (dir / "match.tlog").string()},
                          (dir / "out.txt").string());
  ASSERT_GT(pid, 0);
  TestClient client(151);
  const auto r = client.join(12, "witness");
  ASSERT_TRUE(r && r->result == protocol::JoinResult::accepted) << slurp((dir / "out.txt.err").string());
  ASSERT_TRUE(client.wait_until([&] { return client.snapshots().size() >= 5; }));
  kill(pid, SIGTERM);
  EXPECT_EQ(wait_exit(pid, 10s), 0) << slurp((dir / "out.txt.err").string());
  // Clients are told the match ended.
  EXPECT_TRUE(client.wait_until([&] {
    return !client.match_infos().empty() && client.match_infos().back().state == protocol::MatchState::ended;
  }, 5s));
  // The summary is complete JSON and the log says what happened.
  const auto j = nlohmann::json::parse(slurp(summary));
  EXPECT_GT(j["ticks"].get<std::uint64_t>(), 5u);
  EXPECT_EQ(j["clients"].size(), 1u);
  const auto err = slurp((dir / "out.txt.err").string());
  EXPECT_NE(err.find("SIGTERM received"), std::string::npos) << err;
  EXPECT_NE(slurp((dir / "out.txt").string()).find("throng-server summary"), std::string::npos);
  // The match log it wrote replays bit-exactly: every tick's state hash matches.
  const pid_t replay = spawn({std::string(THRONG_BIN_DIR) + "/throng-replay", "verify", (dir / "match.tlog").string()},
                             (dir / "verify.txt").string());
  ASSERT_GT(replay, 0);
  EXPECT_EQ(wait_exit(replay, 60s), 0) << slurp((dir / "verify.txt").string()) << slurp((dir / "verify.txt.err").string());
  std::filesystem::remove_all(dir);
}

std::string http_get(std::uint16_t port, const std::string& path) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    ::close(fd);
    return {};
  }
  const std::string req = "GET " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
  (void)!::write(fd, req.data(), req.size());
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) > 0;) out.append(buf, static_cast<std::size_t>(n));
  ::close(fd);
  return out;
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
}

TEST(ServerProcess, BadCommandLinesAreRejectedWithAClearMessage) {
  const auto dir = temp_dir("cli");
  struct Case {
    std::vector<std::string> args;
    std::string expect;
  };
  const std::vector<Case> cases = {
      {{"--tick-hz", "0"}, "--tick-hz"},
      {{"--domain", "400"}, "--domain"},
      {{"--duration", "nan"}, "--duration"},
      {{"--client-timeout", "inf"}, "--client-timeout"},
      {{"--scene", "/no/such/scene.json"}, "neither a built-in scene"},
      {{"--bogus"}, "bogus"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> argv{kServer};
    argv.insert(argv.end(), c.args.begin(), c.args.end());
    argv.insert(argv.end(), {"--no-log", "--admin-port", "-1", "--domain", "153"});
    if (c.args[0] == "--domain") argv.resize(argv.size() - 2);
    const auto out = (dir / "out.txt").string();
    const pid_t pid = spawn(argv, out);
    ASSERT_GT(pid, 0);
    const int code = wait_exit(pid, 20s);
    EXPECT_NE(code, 0) << c.args[0];
    const auto err = slurp(out + ".err");
    EXPECT_NE(err.find(c.expect), std::string::npos) << "for " << c.args[0] << " got: " << err;
  }
  const pid_t pid = spawn({kServer, "--help"}, (dir / "help.txt").string());
  EXPECT_EQ(wait_exit(pid, 10s), 0);
  EXPECT_NE(slurp((dir / "help.txt").string()).find("--interest-radius"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace throng::test
