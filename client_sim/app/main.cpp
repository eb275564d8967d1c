// throng-bots: connects N simulated clients to a running throng-server over the real client
// path (DDS), drives them with a behavior, and reports command-to-applied latency, snapshot
// arrival/gaps, bandwidth and join times (human summary on stdout, JSON with --json). --ramp
// finds the largest client count the server sustains.
//
// Exit codes: 0 ok (also after Ctrl-C), 1 bad usage or DDS error, 2 no server on the domain,
// 3 some bots failed to join.
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <thread>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "driver.h"
#include "options.h"
#include "progress.h"
#include "ramp_mode.h"
#include "throng/client_sim/behavior.h"
#include "throng/client_sim/fleet.h"
#include "throng/client_sim/report.h"
#include "throng/protocol/security.h"

namespace {

std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void on_signal(int) {
  g_stop.store(true);
  // A second Ctrl-C ends at once.
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace throng;
  bots::Options o;
  CLI::App app{"throng-bots: simulated clients for a running throng-server"};
  app.option_defaults()->always_capture_default();
  app.add_option("--clients", o.clients, "number of bots")->check(CLI::Range(1u, 100000u));
  app.add_option("--duration", o.duration_s, "seconds to run after connecting")->check(CLI::PositiveNumber);
  app.add_option("--domain", o.domain, "DDS domain id")->check(CLI::Range(0, 231));
  app.add_option("--behavior", o.behavior,
                 "wander|charge|waypoints|idle|nan|flood|hijack|stale|mix, or a comma-separated list "
                 "(bot i gets entry i mod n)")
      ->check([](const std::string& v) {
        try {
          client_sim::expand_behavior_spec(v);
          return std::string();
        } catch (const std::exception& e) {
          return std::string(e.what());
        }
      });
  app.add_option("--json", o.json_path, "write the JSON report to this file");
  app.add_flag("--participant-per-client", o.participant_per_client,
               "one DDS participant per bot (default: all bots share one)");
  app.add_flag("--loopback,!--no-loopback", o.loopback,
               "DDS on 127.0.0.1 only (default) or Fast DDS's default transports and discovery");
  app.add_option("--server", o.server,
                 "udp://HOST:PORT or tcp://HOST:PORT: reach a server started with --listen (no multicast; udp:// crosses NAT)")
      ->check(protocol::check_endpoint);
  app.add_option("--security", o.security_dir,
                 "DDS Security: directory made by throng-pki; the bots authenticate as the bot fleet identity")
      ->check(CLI::ExistingDirectory);
  app.add_option("--identity", o.identity, "identity in the --security directory: bots (default), operator, or a "
                                           "player made with throng-pki client");
  app.add_flag("--ramp", o.ramp, "ramp mode: add bots step by step until the server stops keeping up");
  app.add_option("--ramp-start", o.ramp_options.start, "bots in the first step")->check(CLI::Range(1u, 100000u));
  app.add_option("--ramp-step", o.ramp_options.step, "bots added per step")->check(CLI::Range(1u, 100000u));
  app.add_option("--ramp-step-s", o.ramp_options.step_s, "measuring window per step, seconds")
      ->check(CLI::PositiveNumber);
  app.add_option("--ramp-settle-s", o.ramp_options.settle_s, "pause after a step's joins before measuring")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--ramp-max", o.ramp_options.max_clients, "stop after this many bots")
      ->check(CLI::Range(1u, 100000u));
  app.add_option("--seed", o.seed, "seed for nonces and behaviors (0: random)");
  app.add_option("--server-wait", o.server_wait_s, "seconds to wait for the server")->check(CLI::PositiveNumber);
  app.add_option("--join-timeout", o.join_timeout_s, "seconds a bot waits for its join reply")
      ->check(CLI::PositiveNumber);
  app.add_option("--rejoin-after", o.rejoin_after_s,
                 "seconds without a snapshot after which a joined bot joins again as a new client (its server died "
                 "and nobody took the match over); 0 = never. The report counts rejoins")
      ->check([](const std::string& v) {
        // CLI::Range lets NaN through (every comparison with it is false).
        try {
          const double d = std::stod(v);
          return std::isfinite(d) && d >= 0.0 && d <= 3600.0 ? std::string() : std::string("must be 0..3600 seconds");
        } catch (const std::exception&) {
          return std::string("must be a number of seconds");
        }
      });
  app.add_option("--name-prefix", o.name_prefix, "bot names are <prefix>-<index>-<behavior>");
  app.add_option("--send-phases", o.send_phases,
                 "spread the bots' sends over this many phases of the server tick (1: all at once)")
      ->check(CLI::Range(1u, 64u));
  bool quiet = false;
  app.add_flag("--quiet,-q", quiet, "no progress line");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;  // --help: 0; any usage error: 1
  }
  o.progress = !quiet;
  if (o.participant_per_client && o.server.rfind("tcp://", 0) == 0) {
    // Fast DDS 2.9 keys a client's TCP connection by its host and process id (a client has no
    // listening port), so one process's participants would share one key at the server, which
    // then delivers to one of them only: none of the bots joined.
    fmt::print(stderr,
               "throng-bots: --participant-per-client does not work with --server (TCP): the server tells TCP clients "
               "apart by host and process; run one throng-bots process per participant instead\n");
    return 1;
  }

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  client_sim::FleetOptions fo;
  fo.domain_id = o.domain;
  fo.loopback_only = o.loopback;
  if (!o.server.empty()) fo.server_endpoint = protocol::parse_endpoint(o.server);
  fo.participant_per_client = o.participant_per_client;
  if (!o.security_dir.empty()) {
    try {
      fo.security = protocol::security_files(o.security_dir, o.identity);
    } catch (const std::exception& e) {
      fmt::print(stderr, "throng-bots: {}\n", e.what());
      return 1;
    }
  }
  fo.behavior = o.behavior;
  fo.name_prefix = o.name_prefix;
  fo.seed = o.seed;
  fo.phases_per_tick = o.send_phases;
  fo.server_wait = std::chrono::milliseconds(static_cast<long>(o.server_wait_s * 1000));
  fo.join_timeout = std::chrono::milliseconds(static_cast<long>(o.join_timeout_s * 1000));
  fo.rejoin_after = std::chrono::milliseconds(static_cast<long>(o.rejoin_after_s * 1000));

  try {
    client_sim::Fleet fleet(fo);
    if (!fleet.connect()) {
      fmt::print(stderr, "throng-bots: no server on domain {} within {:g} s\n", o.domain, o.server_wait_s);
      return 2;
    }
    const auto start = client_sim::Clock::now();
    bots::ProgressLine progress(o.progress);
    std::optional<client_sim::RampResult> ramp;
    bots::DriveEnd end = bots::DriveEnd::time_up;
    if (o.ramp) {
      ramp = bots::run_ramp(fleet, o, g_stop, progress);
    } else {
      fleet.launch(o.clients);
      end = bots::drive_for(fleet, o.duration_s, g_stop, progress);
    }
    progress.finish();
    if (g_stop.load()) fmt::print(stderr, "throng-bots: interrupted, leaving\n");
    if (end == bots::DriveEnd::server_ended) fmt::print(stderr, "throng-bots: the server's match ended\n");

    client_sim::RunReport report;
    report.tick_hz = fleet.tick_hz();
    report.duration_s = std::chrono::duration<double>(client_sim::Clock::now() - start).count();
    report.behavior = o.behavior;
    report.bots = fleet.reports();
    report.server_stats = fleet.last_server_stats();
    report.ramp = std::move(ramp);

    fleet.leave_all();
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // let the reliable leaves go out

    std::fputs(client_sim::to_text(report).c_str(), stdout);
    std::fflush(stdout);
    if (!o.json_path.empty()) {
      std::ofstream out(o.json_path);
      out << client_sim::to_json(report).dump(2) << '\n';
      if (!out) {
        fmt::print(stderr, "throng-bots: cannot write {}\n", o.json_path);
        return 1;
      }
    }
    const auto agg = client_sim::aggregate(report);
    if (agg.join_failed > 0) {
      fmt::print(stderr, "throng-bots: {} of {} bots failed to join\n", agg.join_failed, agg.clients);
      return 3;
    }
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "throng-bots: {}\n", e.what());
    return 1;
  }
}
