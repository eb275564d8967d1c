#pragma once
// Opening the log every subcommand starts with: a file that cannot be read as a match log is
// "throng-replay <command>: <why>" on stderr and exit code 2 (kExitBadInput) for the caller.
#include <cstdio>
#include <exception>
#include <memory>
#include <string>
#include <utility>

#include <fmt/format.h>

namespace throng::replay {

// T is matchlog::MatchLogReader or matchlog::LogPlayer (both open from a path, with T's further
// constructor arguments, and throw on a bad file). nullptr after printing the reason.
template <class T, class... Args>
std::unique_ptr<T> open_log(const char* command, const std::string& path, Args&&... args) {
  try {
    return std::make_unique<T>(path, std::forward<Args>(args)...);
  } catch (const std::exception& e) {
    fmt::print(stderr, "throng-replay {}: {}\n", command, e.what());
    return nullptr;
  }
}

}  // namespace throng::replay
