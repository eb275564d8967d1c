#include "child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <gtest/gtest.h>

extern char** environ;

namespace throng::client_sim::testing {

TempDir::TempDir() {
  std::string tmpl = (std::filesystem::temp_directory_path() / "throng-bots-test-XXXXXX").string();
  if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
  path_ = tmpl;
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

ChildProcess::ChildProcess(const std::string& program, const std::vector<std::string>& args,
                           const std::filesystem::path& out, const std::filesystem::path& err) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<std::string> argv_s{program};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  const int rc = posix_spawn(&pid_, program.c_str(), &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw std::runtime_error("posix_spawn " + program + " failed: " + std::to_string(rc));
}

ChildProcess::~ChildProcess() {
  if (pid_ > 0 && !status_) {
    ::kill(pid_, SIGKILL);
    int st = 0;
    ::waitpid(pid_, &st, 0);
  }
}

bool ChildProcess::running() { return !wait(std::chrono::milliseconds(0)).has_value(); }

void ChildProcess::signal(int signo) {
  if (pid_ > 0 && !status_) ::kill(pid_, signo);
}

std::optional<int> ChildProcess::wait(std::chrono::milliseconds timeout) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (!status_) {
    int st = 0;
    const pid_t r = ::waitpid(pid_, &st, WNOHANG);
    if (r == pid_) {
      status_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
      break;
    }
    if (std::chrono::steady_clock::now() >= until) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return status_;
}

std::vector<std::string> server_args(int domain, const std::filesystem::path& dir, std::vector<std::string> extra) {
  std::vector<std::string> a{"--scene",       "battle", "--npcs",         "300",
                             "--domain",      std::to_string(domain),
                             "--admin-port",  "-1",     "--duration",     "60",
                             "--summary-json", (dir / "summary.json").string(),
                             "--client-timeout", "60", "--log-level", "warn"};
  a.insert(a.end(), extra.begin(), extra.end());
  return a;
}

std::unique_ptr<ChildProcess> start_server(int domain, const TempDir& dir, std::vector<std::string> extra) {
  return std::make_unique<ChildProcess>(THRONG_BIN_DIR "/throng-server", server_args(domain, dir.path(), std::move(extra)),
                                        dir / "server.out", dir / "server.log");
}

nlohmann::json stop_server_and_read_summary(ChildProcess& server, const TempDir& dir) {
  server.signal(SIGINT);
  const auto code = server.wait(std::chrono::seconds(20));
  EXPECT_TRUE(code.has_value()) << "throng-server did not exit within 20 s of SIGINT";
  EXPECT_EQ(code.value_or(-1), 0) << read_file(dir / "server.log");
  const std::string text = read_file(dir / "summary.json");
  if (text.empty()) {
    ADD_FAILURE() << "no summary JSON; server log:\n" << read_file(dir / "server.log");
    return nlohmann::json::object();
  }
  return nlohmann::json::parse(text);
}

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const nlohmann::json* find_client(const nlohmann::json& summary, const std::string& name) {
  if (!summary.contains("clients")) return nullptr;
  for (const auto& c : summary["clients"])
    if (c.value("name", std::string()) == name) return &c;
  return nullptr;
}

}  // namespace throng::client_sim::testing
