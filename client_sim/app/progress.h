#pragma once
// The live progress line on stderr, once per second: clients joined, snapshots/s, latency p50
// over the last second, kbit/s per client. Overwrites itself on a terminal, one line per second
// otherwise (logs stay readable).
#include <cstdint>

#include "throng/client_sim/fleet.h"

namespace throng::bots {

class ProgressLine {
 public:
  explicit ProgressLine(bool enabled);
  // Prints when a second has passed since the last line.
  void update(client_sim::Fleet& fleet);
  void finish();  // ends an overwritten line

 private:
  bool enabled_;
  bool tty_;
  bool printed_ = false;
  client_sim::TimePoint start_, last_;
  std::uint64_t last_snapshots_ = 0, last_bytes_ = 0;
};

}  // namespace throng::bots
