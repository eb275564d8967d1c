#pragma once
// The one exception type for bad parameter / policy input.
//
// It derives from std::invalid_argument so callers that only care "was the input bad" (the runtime
// parameter API, scene loading) can catch the standard type, while tools and tests can read the
// JSON path of the offending field separately from the message. The path uses dots for object
// keys and [i] for array items, e.g. "archetypes.cavalry.weight" or "pair_rules[1].b.kind".
#include <stdexcept>
#include <string>

namespace throng::params {

class ConfigError : public std::invalid_argument {
 public:
  ConfigError(const std::string& path, const std::string& message)
      : std::invalid_argument(path.empty() ? message : path + ": " + message),
        path_(path),
        message_(message) {}

  // Where the error is ("" for a whole-document problem such as malformed JSON).
  const std::string& path() const noexcept { return path_; }
  // What is wrong, without the path.
  const std::string& message() const noexcept { return message_; }

 private:
  std::string path_;
  std::string message_;
};

}  // namespace throng::params
