#pragma once
// The one exception type for a bad scene (file, inline object or built-in with bad options).
//
// Same shape as params::ConfigError on purpose: the message starts with the JSON path of the
// offending field ("spawns[2].count: must be >= 0") so a user can fix a file without a debugger,
// and tools/tests can read path() and message() separately. It derives from std::invalid_argument
// so callers that only care "was the input bad" (the bench's exit code 2) catch the standard type.
#include <stdexcept>
#include <string>

namespace throng::scene {

class SceneError : public std::invalid_argument {
 public:
  SceneError(const std::string& path, const std::string& message)
      : std::invalid_argument(path.empty() ? message : path + ": " + message), path_(path), message_(message) {}

  const std::string& path() const noexcept { return path_; }        // "" for whole-document problems
  const std::string& message() const noexcept { return message_; }  // without the path

 private:
  std::string path_;
  std::string message_;
};

}  // namespace throng::scene
