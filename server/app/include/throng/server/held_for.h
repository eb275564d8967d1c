#pragma once
// How long a condition has held, for the rules that end a match once something has lasted long
// enough (--end-when-empty, --end-when-routed): each tick says whether the condition holds, and
// gets back whether it just began, just ended, is still holding, or has held for the limit.
#include <chrono>
#include <optional>

namespace throng::server {

class HeldFor {
 public:
  using Clock = std::chrono::steady_clock;
  enum class State { off, began, holding, elapsed, ended };

  State update(bool holds, Clock::time_point now, double limit_s) {
    if (!holds) {
      const bool was = since_.has_value();
      since_.reset();
      return was ? State::ended : State::off;
    }
    if (!since_) {
      since_ = now;
      return State::began;
    }
    return std::chrono::duration<double>(now - *since_).count() >= limit_s ? State::elapsed : State::holding;
  }

 private:
  std::optional<Clock::time_point> since_;
};

}  // namespace throng::server
