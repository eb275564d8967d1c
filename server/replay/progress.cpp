#include <unistd.h>

#include <chrono>
#include <cstdio>

#include <fmt/format.h>

#include "commands.h"

namespace throng::replay {
namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

Progress::Progress(const char* what, bool enabled)
    : what_(what), enabled_(enabled), tty_(isatty(STDERR_FILENO) == 1), start_s_(now_s()) {}

void Progress::update(std::uint64_t done, std::uint64_t total) {
  if (!enabled_ || total == 0) return;
  const double t = now_s();
  const double pct = 100.0 * static_cast<double>(done) / static_cast<double>(total);
  const double elapsed = t - start_s_;
  const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
  if (tty_) {
    if (t - last_print_s_ < 0.1 && done != total) return;
    last_print_s_ = t;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(pct / 100.0 * kWidth);
    fmt::print(stderr, "\r{} [{:<{}}] {:5.1f}%  tick {}/{}  {:.0f} ticks/s ", what_, std::string(static_cast<std::size_t>(filled), '#'),
               kWidth, pct, done, total, rate);
    std::fflush(stderr);
  } else {
    const int decile = static_cast<int>(pct / 10.0);
    if (decile == last_decile_) return;
    last_decile_ = decile;
    fmt::print(stderr, "{}: {:.0f}% (tick {}/{}, {:.0f} ticks/s)\n", what_, pct, done, total, rate);
  }
}

void Progress::finish() {
  if (enabled_ && tty_) fmt::print(stderr, "\n");
}

}  // namespace throng::replay
