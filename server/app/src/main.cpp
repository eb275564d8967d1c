// throng-server: hosts one match. All the work is in MatchServer; main only parses, sets up
// logging and turns exceptions into a clear message and a non-zero exit code.
#include <csignal>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "throng/server/log_setup.h"

#include "throng/server/match_server.h"
#include "throng/server/server_options.h"

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f) must end the match log like a full disk does, with a write error
  // the server reports and survives, not kill the match with SIGXFSZ.
  std::signal(SIGXFSZ, SIG_IGN);
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
    throng::server::MatchServer server(*parsed.options);
    return server.run();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
