// throng-server: hosts one match. All the work is in MatchServer; main only parses, sets up
// logging and turns exceptions into a clear message and a non-zero exit code.
#include <malloc.h>

#include <csignal>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "throng/server/log_setup.h"

#include "throng/server/match_server.h"
#include "throng/server/server_options.h"
#include "throng/server/standby_server.h"

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f) must end the match log like a full disk does, with a write error
  // the server reports and survives, not kill the match with SIGXFSZ.
  std::signal(SIGXFSZ, SIG_IGN);
  // Blocks of 128 KiB and more (keyframe checkpoints, their compressed copies, the log's blocks, a
  // restored match's tables) always get a mapping of their own, returned whole when freed. Why:
  // glibc raises this threshold each time it frees such a mapping, after which the next ones come
  // from the heap and leave holes between longer-lived blocks; a server that runs for hours while
  // clients come and go then grows. At 1 MiB the compressed keyframes (about 0.4 MB, a little
  // larger with each as a battle densifies) still came from a thread's arena, which kept growing
  // (docs/design/memory.md). Setting it also fixes the heap's trim threshold at its default.
  mallopt(M_MMAP_THRESHOLD, 128 << 10);
  const std::vector<std::string> args(argv + 1, argv + argc);
  const auto parsed = throng::server::parse_server_options(args);
  if (!parsed.options) {
    std::fputs((parsed.message + "\n").c_str(), parsed.exit_code == 0 ? stdout : stderr);
    return parsed.exit_code;
  }
  // Logs go to stderr so stdout carries only the summary (scripts can capture it).
  throng::server::configure_logging(
      parsed.options->log_format == "json" ? throng::server::LogFormat::json : throng::server::LogFormat::text,
      parsed.options->log_level);
  try {
    if (parsed.options->standby) {
      throng::server::StandbyServer standby(*parsed.options);
      return standby.run();
    }
    throng::server::MatchServer server(*parsed.options);
    return server.run();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
