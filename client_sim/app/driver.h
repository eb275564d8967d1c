#pragma once
// The shared loop: Fleet::step() phases_per_tick times per server tick drives every bot, each
// once per tick (no thread per bot).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

#include "progress.h"
#include "throng/client_sim/fleet.h"

namespace throng::bots {

enum class DriveEnd { time_up, interrupted, server_ended, condition };

// Steps the fleet at its step period until `seconds` pass, `stop` is set, the server's
// match ends, or done() (checked after every step) returns true.
template <typename Done>
DriveEnd drive(client_sim::Fleet& fleet, double seconds, const std::atomic<bool>& stop, ProgressLine& progress,
               Done&& done) {
  using client_sim::Clock;
  const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  auto next = Clock::now();
  for (;;) {
    if (stop.load()) return DriveEnd::interrupted;
    if (Clock::now() >= until) return DriveEnd::time_up;
    if (fleet.server_ended()) return DriveEnd::server_ended;
    fleet.step();
    progress.update(fleet);
    if (done()) return DriveEnd::condition;
    const auto period =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(fleet.step_period_s()));
    next += period;
    const auto now = Clock::now();
    if (next < now - period) next = now;  // fell behind by more than a step: do not burst to catch up
    std::this_thread::sleep_until(std::min(next, until));
  }
}

inline DriveEnd drive_for(client_sim::Fleet& fleet, double seconds, const std::atomic<bool>& stop,
                          ProgressLine& progress) {
  return drive(fleet, seconds, stop, progress, [] { return false; });
}

}  // namespace throng::bots
