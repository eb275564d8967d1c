#include "throng/server/tick_schedule.h"

#include <stdexcept>

namespace throng::server {

TickSchedule::TickSchedule(Duration period, std::uint32_t max_catchup, TimePoint start)
    : period_(period), max_catchup_(max_catchup), deadline_(start) {
  if (period <= Duration::zero()) throw std::invalid_argument("tick period must be positive");
}

void TickSchedule::begin_tick(TimePoint now) {
  ++ticks_;
  deadline_ += period_;
  // How many whole periods the schedule is behind after this tick: those ticks would all run back
  // to back. Beyond max_catchup, forget them and continue from now.
  if (now > deadline_) {
    const auto behind = static_cast<std::uint64_t>((now - deadline_) / period_);
    if (behind > max_catchup_) {
      skipped_ += behind - max_catchup_;
      deadline_ += period_ * static_cast<Duration::rep>(behind - max_catchup_);
    }
  }
}

bool TickSchedule::end_tick(TimePoint now) {
  const bool overrun = now > deadline_;
  if (overrun) ++overruns_;
  return overrun;
}

}  // namespace throng::server
