#include "progress.h"

#include <fmt/core.h>

namespace throng::bench {

namespace {
constexpr double kPrintEvery_s = 2.0;
}

Progress::Progress(std::string label, std::uint64_t total_ticks, bool enabled)
    : label_(std::move(label)), total_(total_ticks), enabled_(enabled), start_(Clock::now()), last_print_(start_) {}

void Progress::tick(std::uint64_t done, double last_tick_us) {
  if (!enabled_) return;
  const auto now = Clock::now();
  if (std::chrono::duration<double>(now - last_print_).count() < kPrintEvery_s) return;
  last_print_ = now;
  printed_ = true;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double eta = done ? elapsed * double(total_ - done) / double(done) : 0.0;
  fmt::print(stderr, "[{}] tick {}/{} ({:.0f}%), last tick {:.0f} us, {:.0f} s left\n", label_, done, total_,
             100.0 * double(done) / double(total_), last_tick_us, eta);
}

void Progress::done() {
  if (!enabled_ || !printed_) return;
  const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  fmt::print(stderr, "[{}] {} ticks in {:.1f} s\n", label_, total_, elapsed);
}

}  // namespace throng::bench
