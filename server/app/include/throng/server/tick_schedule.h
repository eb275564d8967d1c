#pragma once
// When the next tick runs: absolute deadlines (deadline += period, so rounding and wake-up jitter
// never accumulate into drift) with a bounded catch-up after a stall.
//
// Pure arithmetic on time points, no clock and no timer, so its rules are tested exactly with
// synthetic times (tests/server/tick_schedule_test.cpp) and the Asio loop only asks it questions.
// After a stall (a debugger, a page-in, a slow disk) the server runs up to max_catchup ticks back
// to back to recover simulated time; if it is further behind than that, it gives up on the lost
// time (counted as skipped ticks) instead of spiralling: a match that pauses briefly is better
// than one that runs fast for seconds.
#include <chrono>
#include <cstdint>

namespace throng::server {

class TickSchedule {
 public:
  using Clock = std::chrono::steady_clock;
  using Duration = Clock::duration;
  using TimePoint = Clock::time_point;

  TickSchedule(Duration period, std::uint32_t max_catchup, TimePoint start);

  // The time the next tick is due.
  TimePoint next_deadline() const { return deadline_; }

  // Call when a tick is about to run at `now` (now >= next_deadline()). Advances the deadline by
  // one period; if that leaves the schedule more than max_catchup periods behind `now`, the
  // deadline is rebased to now and the ticks given up are added to skipped().
  void begin_tick(TimePoint now);

  // Call when the tick's work is done: a tick that ends after the next deadline is an overrun.
  // Returns true for an overrun.
  bool end_tick(TimePoint now);

  std::uint64_t ticks() const { return ticks_; }
  std::uint64_t overruns() const { return overruns_; }
  std::uint64_t skipped() const { return skipped_; }
  Duration period() const { return period_; }

 private:
  Duration period_;
  std::uint32_t max_catchup_;
  TimePoint deadline_;
  std::uint64_t ticks_ = 0;
  std::uint64_t overruns_ = 0;
  std::uint64_t skipped_ = 0;
};

}  // namespace throng::server
