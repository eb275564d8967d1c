#include "progress.h"

#include <unistd.h>

#include <cstdio>

#include <fmt/format.h>

namespace throng::bots {

ProgressLine::ProgressLine(bool enabled)
    : enabled_(enabled), tty_(isatty(STDERR_FILENO) == 1), start_(client_sim::Clock::now()), last_(start_) {}

void ProgressLine::update(client_sim::Fleet& fleet) {
  const auto now = client_sim::Clock::now();
  const double dt = std::chrono::duration<double>(now - last_).count();
  if (dt < 1.0) return;
  const auto p = fleet.progress();
  const auto window = fleet.take_window_latency().summary();
  const double snaps_per_s = static_cast<double>(p.snapshots - last_snapshots_) / dt;
  const double kbps = p.active ? static_cast<double>(p.bytes - last_bytes_) * 8.0 / 1000.0 / dt / p.active : 0.0;
  last_snapshots_ = p.snapshots;
  last_bytes_ = p.bytes;
  last_ = now;
  if (!enabled_) return;
  const auto line = fmt::format("[{:6.1f} s] clients {}/{} joined{}  snapshots {:.0f}/s  latency p50 {:.1f} ms  "
                                "{:.1f} kbit/s/client  missed {}  sent {}",
                                std::chrono::duration<double>(now - start_).count(), p.active, p.launched,
                                p.failed ? fmt::format(" ({} failed)", p.failed) : std::string(), snaps_per_s,
                                window.p50, kbps, p.missed_ticks, p.commands_sent);
  if (tty_) {
    std::fprintf(stderr, "\r%s\x1b[K", line.c_str());
  } else {
    std::fprintf(stderr, "%s\n", line.c_str());
  }
  std::fflush(stderr);
  printed_ = true;
}

void ProgressLine::finish() {
  if (enabled_ && tty_ && printed_) std::fprintf(stderr, "\n");
  printed_ = false;
}

}  // namespace throng::bots
