// throng-view: a thin-client gateway. Joins a running throng-server as an ordinary client over
// DDS (the bots' path) and serves a web page that draws the client's view of the match and lets a
// person control its character (HTTP + WebSocket, Boost.Beast). The page protocol is in
// client_sim/view/README.md, the threads in gateway_loop.h. With --log FILE it plays a match log
// instead, without a server (log_loop.h): the same page with a timeline.
#include <atomic>
#include <csignal>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "gateway_loop.h"
#include "throng/protocol/dds_transport.h"
#include "log_loop.h"
#include "throng/view/log_control.h"

namespace {

std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void on_signal(int) {
  g_stop.store(true);
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends at once
  std::signal(SIGTERM, SIG_DFL);
}

}  // namespace

int main(int argc, char** argv) {
  throng::view::ViewOptions o;
  throng::view::LogViewOptions lo;
  CLI::App app{
      "throng-view: joins a throng-server match as a client over DDS and serves a page that draws it and "
      "controls the character (http://127.0.0.1:PORT/); with --log FILE it plays a match log instead, "
      "without a server, with a timeline to scrub, pause and change speed"};
  app.option_defaults()->always_capture_default();
  // Log mode. Whether the file is a playable log is checked by run_log_view (exit 2), not here
  // (CLI errors exit 1), so a missing file and a corrupt one read the same way.
  auto* log = app.add_option("--log", lo.log, "play this match log (.tlog) instead of joining a server");
  app.add_option("--speed", lo.speed, "--log: playback speed (0.25 to 8)")
      // CLI::Range lets NaN through (every comparison with it is false).
      ->check([](const std::string& v) {
        try {
          const double x = std::stod(v);
          if (x >= throng::view::kMinSpeed && x <= throng::view::kMaxSpeed) return std::string();
        } catch (const std::exception&) {
        }
        return std::string("a number from 0.25 to 8");
      })
      ->needs(log);
  // CLI11 would wrap "-3" into a huge unsigned tick: refuse negatives as a usage error.
  app.add_option("--from", lo.from, "--log: start at this tick")->check(CLI::NonNegativeNumber)->needs(log);
  app.add_flag("--paused", lo.paused, "--log: start paused")->needs(log);
  auto* domain = app.add_option("--domain", o.domain, "DDS domain id of the server")->check(CLI::Range(0, 231));
  app.add_option("--port", o.port, "HTTP/WebSocket port (0 = any free port)")->check(CLI::Range(0, 65535));
  app.add_option("--bind", o.bind, "address to serve the page on (0.0.0.0 = every interface)");
  auto* name = app.add_option("--name", o.name, "client name the server logs (at most 64 bytes)")
      ->check([](const std::string& v) { return v.size() <= 64 ? std::string() : std::string("at most 64 bytes"); });
  auto* server_wait = app.add_option("--server-wait", o.server_wait_s, "seconds to wait for the server")->check(CLI::PositiveNumber);
  auto* join_timeout = app.add_option("--join-timeout", o.join_timeout_s, "seconds to wait for the join reply")->check(CLI::PositiveNumber);
  app.add_flag("--loopback,!--no-loopback", o.loopback,
               "DDS on 127.0.0.1 only (default) or Fast DDS's default transports and discovery");
  auto* server = app.add_option("--server", o.server, "udp://HOST:PORT or tcp://HOST:PORT: reach a server started with --listen")
                     ->check(throng::protocol::check_endpoint);
  auto* security = app.add_option("--security", o.security_dir,
                                  "DDS Security: directory made by throng-pki; needs --identity")
                      ->check(CLI::ExistingDirectory);
  auto* identity = app.add_option("--identity", o.identity,
                                  "with --security: the player (throng-pki client DIR NAME) or 'operator' to view as")
                       ->needs(security);
  security->needs(identity);
  app.add_option("--web-root", o.web_root,
                 "serve the page from this folder instead of the copy built into the binary (for editing)")
      ->check(CLI::ExistingDirectory);
  app.add_flag("--quiet,-q", o.quiet, "no status line every 10 s");
  for (auto* live_only : {domain, name, server_wait, join_timeout, security, identity, server}) log->excludes(live_only);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  if (!lo.log.empty()) {
    lo.bind = o.bind;
    lo.port = o.port;
    lo.web_root = o.web_root;
    lo.quiet = o.quiet;
    return throng::view::run_log_view(lo, g_stop);
  }
  return throng::view::run_gateway(o, g_stop);
}
