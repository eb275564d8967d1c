#pragma once
// Test helpers: a child process (throng-server, throng-bots) with bounded waits, killed in the
// destructor if still running, and a temporary directory removed at the end.
#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace throng::client_sim::testing {

class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

class ChildProcess {
 public:
  // Starts `program args...` with stdout/stderr redirected to the given files.
  ChildProcess(const std::string& program, const std::vector<std::string>& args, const std::filesystem::path& out,
               const std::filesystem::path& err);
  ~ChildProcess();  // SIGKILL + reap if still running
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  bool running();
  void signal(int signo);
  // The exit code (128 + signal when killed by one), or nullopt if still running after timeout.
  std::optional<int> wait(std::chrono::milliseconds timeout);

 private:
  pid_t pid_ = -1;
  std::optional<int> status_;
};

// throng-server from THRONG_BIN_DIR with the test defaults (loopback, no admin port, summary in
// dir/summary.json, log in dir/server.log).
std::vector<std::string> server_args(int domain, const std::filesystem::path& dir, std::vector<std::string> extra);
std::unique_ptr<ChildProcess> start_server(int domain, const TempDir& dir, std::vector<std::string> extra = {});
// Interrupts the server, waits (bounded) for it to exit and reads its summary JSON.
nlohmann::json stop_server_and_read_summary(ChildProcess& server, const TempDir& dir);

std::string read_file(const std::filesystem::path& p);
const nlohmann::json* find_client(const nlohmann::json& summary, const std::string& name);

}  // namespace throng::client_sim::testing
