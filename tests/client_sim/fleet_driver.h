#pragma once
// Drives a Fleet in a test the way throng-bots does (one step per send phase), bounded.
#include <chrono>
#include <thread>

#include "throng/client_sim/fleet.h"

namespace throng::client_sim::testing {

// Steps until done() or `seconds` passed; returns whether done() became true.
template <typename Done>
bool drive_until(Fleet& fleet, double seconds, Done&& done) {
  const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  auto next = Clock::now();
  while (Clock::now() < until) {
    fleet.step();
    if (done()) return true;
    next += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(fleet.step_period_s()));
    if (next < Clock::now()) next = Clock::now();
    std::this_thread::sleep_until(next);
  }
  return false;
}

inline void drive_for(Fleet& fleet, double seconds) {
  drive_until(fleet, seconds, [] { return false; });
}

// Every launched bot has its first snapshot (or failed).
inline bool all_active(const Fleet& fleet) {
  const auto p = fleet.progress();
  return p.active == p.launched;
}

}  // namespace throng::client_sim::testing
