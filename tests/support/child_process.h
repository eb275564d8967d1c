#pragma once
// Test support shared by every suite that runs our binaries: a child process with bounded waits
// (killed in the destructor if still running), a temporary directory removed at the end, and
// reading a whole file (logs, summaries).
#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace throng::test {

class TempDir {
 public:
  explicit TempDir(const std::string& prefix = "throng-test");
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
  // Starts `program args...` with stdin from /dev/null and stdout/stderr into the given files.
  // own_group: the child leads a new process group and the destructor kills the whole group
  // (for programs with helper processes, such as Chromium).
  ChildProcess(const std::string& program, const std::vector<std::string>& args, const std::filesystem::path& out,
               const std::filesystem::path& err, bool own_group = false);
  ~ChildProcess();  // kill_now()
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  bool running();
  void signal(int signo);
  // The exit code (128 + signal when killed by one), or nullopt if still running after timeout.
  std::optional<int> wait(std::chrono::milliseconds timeout);
  void kill_now();  // SIGKILL (the group when own_group) + reap, if still running

 private:
  pid_t pid_ = -1;
  bool own_group_ = false;
  std::optional<int> status_;
};

std::string read_file(const std::filesystem::path& p);  // "" if it cannot be read

}  // namespace throng::test
