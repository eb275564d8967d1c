#pragma once
// throng-view --log: plays a match log behind the same page, without a server or DDS. Threads:
//  - the web thread (WebServer): parses and validates page messages (log_control.h) into a queue;
//  - the loop thread (run_log_view): the LogPlayer (a re-simulated Match), the LogController
//    (play/pause/speed/seek against the wall clock), frames to the pages.
// A seek runs on the loop thread and blocks it (without world keyframes in the log a backwards
// seek re-simulates from the match start): a "timeline" message with seeking=true goes out first
// so the page can say so, and page messages arriving meanwhile wait in the queue (seeks coalesce).
#include <atomic>
#include <cstdint>
#include <string>

namespace throng::view {

struct LogViewOptions {
  std::string log;  // the .tlog file
  std::string bind = "127.0.0.1";
  int port = 8088;
  std::string web_root;
  double speed = 1.0;       // [kMinSpeed, kMaxSpeed]
  std::uint64_t from = 0;   // start tick
  bool paused = false;      // start paused at `from`
  bool quiet = false;
};

// Exit codes: 0 stopped (SIGINT/SIGTERM), 1 port in use, 2 the log cannot be played (missing,
// not a log, corrupt header, no complete tick, --from beyond its last tick).
int run_log_view(const LogViewOptions& options, const std::atomic<bool>& stop);

}  // namespace throng::view
