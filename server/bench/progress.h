#pragma once
// Progress lines on stderr for long runs, at most one every two seconds (stdout stays clean for
// --json). Wall-clock time only decides *whether* to print, never anything the world sees.
#include <chrono>
#include <cstdint>
#include <string>

namespace throng::bench {

class Progress {
 public:
  Progress(std::string label, std::uint64_t total_ticks, bool enabled);
  void tick(std::uint64_t done, double last_tick_us);
  void done();

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  std::uint64_t total_;
  bool enabled_;
  bool printed_ = false;
  Clock::time_point start_;
  Clock::time_point last_print_;
};

}  // namespace throng::bench
