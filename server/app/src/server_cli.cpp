// throng-server's command line. CLI11 gives --help and type errors; ranges that CLI11 cannot
// express (a finite double, a port or -1) are checked here so every bad value gets a message that
// names the option.
#include <cmath>
#include <stdexcept>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "throng/protocol/dds_transport.h"
#include "throng/server/agones_sdk.h"
#include "throng/server/memory_trimmer.h"
#include "throng/server/server_options.h"

namespace throng::server {

namespace {

void require_finite(double v, const char* option) {
  if (!std::isfinite(v)) throw CLI::ValidationError(option, "must be a finite number");
}

}  // namespace

ParseResult parse_server_options(const std::vector<std::string>& args) {
  ServerOptions o;
  auto& m = o.match;
  CLI::App app{
      "throng-server: hosts one authoritative crowd-battle match over DDS.\n"
      "Clients join, send commands and receive snapshots of the objects near their camera; NPCs\n"
      "are driven by the battle AI. Stops after --duration, --end-when-empty or on SIGINT/SIGTERM (graceful).\n"
      "Under Agones (AGONES_SDK_HTTP_PORT set) it reports ready, health and shutdown to the SDK sidecar.",
      "throng-server"};
  app.option_defaults()->always_capture_default();
  app.add_option("--scene", o.scene, "built-in scene (battle, crush, street, obstacles, mixed, one_cell) or scene JSON file");
  app.add_option("--npcs", o.npcs, "scale the scene to this many bodies at the same density (0 = scene's own count)")
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{1'000'000}));
  app.add_option("--tick-hz", m.tick_hz, "simulation and snapshot rate")->check(CLI::Range(1u, 240u));
  app.add_option("--domain", o.domain, "DDS domain id")->check(CLI::Range(0, 231));
  app.add_flag("!--network", o.loopback_only,
               "use Fast DDS's default transports and discovery (real network) instead of 127.0.0.1 only");
  app.add_option("--listen", o.listen,
                 "udp://ADDR:PORT: DDS over UDP on that one port, reaching clients behind NAT (needs --public-address "
                 "with 0.0.0.0); clients connect with --server udp://HOST:PORT. tcp://ADDR:PORT: DDS over TCP only "
                 "(0.0.0.0 = every interface); clients connect with --server tcp://HOST:PORT. Neither uses multicast: "
                 "for clouds and NAT. 'agones': the TCP port Agones "
                 "allocated to the GameServer's port named dds (portPolicy Passthrough), told as the node's address")
      ->check([](const std::string& v) { return v == kListenAgones ? std::string() : protocol::check_endpoint(v); });
  app.add_option("--public-address", o.public_address,
                 "with --listen: the IPv4 address clients reach the server at, when it is not the listening one "
                 "(NAT, a cloud load balancer)");
  app.add_option("--duration", o.duration_s, "seconds to run (0 = until SIGINT/SIGTERM)")->check(CLI::Range(0.0, 1e7));
  app.add_option("--admin-port", o.admin_port, "admin HTTP port (/healthz /readyz /metrics); 0 = any free port, -1 = off")
      ->check(CLI::Range(-1, 65535));
  app.add_option("--admin-bind", o.admin_bind, "admin HTTP bind address");
  app.add_option("--max-clients", m.max_clients, "clients admitted at once; more are refused (match_full)")
      ->check(CLI::Range(1u, 4096u));
  app.add_option("--client-timeout", m.client_timeout_s, "seconds without a command before a client is dropped")
      ->check(CLI::Range(0.1, 3600.0));
  app.add_option("--max-commands-per-tick", m.max_commands_per_tick, "per client; more in one tick are rejected (rate_limited)")
      ->check(CLI::Range(1u, 1000u));
  app.add_option("--interest-radius", m.interest.radius_m, "metres around a client's camera it receives objects from (0 = whole world)")
      ->check(CLI::Range(0.0, 100000.0));
  double client_kbps = m.interest.budget_bytes * 8.0 * m.tick_hz / 1000.0;
  app.add_option("--client-kbps", client_kbps, "snapshot budget per client in kbit/s (0 = unlimited)")
      ->check(CLI::Range(0.0, 1e6));
  app.add_option("--player-speed", m.player_speed_mps, "m/s of a player moving at full stick")->check(CLI::Range(0.1, 50.0));
  app.add_option("--npc-speed", m.npc_speed_mps, "m/s NPCs march at")->check(CLI::Range(0.0, 50.0));
  app.add_option("--threads", m.worker_threads, "threads building and publishing snapshots (results do not depend on it)")
      ->check(CLI::Range(1u, 64u));
  app.add_option("--solver-threads", m.solver_threads,
                 "threads sweeping the crowd solve (results do not depend on it; helps crowds of 10,000 bodies and more)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 64u));
  app.add_option("--log", o.log_file, "match log file (replay with throng-replay); default <--log-dir>/<match id>.tlog");
  bool no_log = false;
  app.add_flag("--no-log", no_log, "do not write a match log");
  app.add_flag("--log-baselines", o.log_baselines,
               "keep the snapshot baselines in the log's keyframes, so throng-replay play publishes byte for byte what "
               "the server sent from any seek on (about 3x larger keyframes with 50 clients)");
  app.add_option("--log-keyframe-ticks", o.log_keyframe_ticks,
                 "a world keyframe in the match log every N ticks (rounded up to 15; 0 = none): a seek re-simulates up "
                 "to N ticks, and keyframes are most of a log's size")
      ->check(CLI::Range(0u, 108000u));
  app.add_option("--security", o.security_dir,
                 "DDS Security: directory made by throng-pki (the server identity in DIR/server); only authenticated "
                 "participants join, traffic is encrypted, and only operator identities may change parameters")
      ->check(CLI::ExistingDirectory);
  app.add_flag("--allow-anonymous-operator", o.allow_anonymous_operator,
               "accept parameter changes (ParamUpdate) from any participant: for development, tests and local tools "
               "only, never on a reachable network. Without it and without --security every change is refused "
               "(\"not an operator\")");
  app.add_option("--end-when-empty", o.end_when_empty_s,
                 "end the match once every player has left and nobody joined for this many seconds (counted after a "
                 "first player joined; 0 = never). Under Agones the server then calls /shutdown")
      ->check(CLI::Range(0.0, 1e7));
  app.add_option("--end-when-routed", o.end_when_routed_s,
                 "end the match once one side has been routed (every NPC group of a faction retreating) for this many "
                 "seconds (0 = never)")
      ->check(CLI::Range(0.0, 1e7));
  app.add_flag("--standby", o.standby,
               "be a hot standby of the match on this DDS domain instead of hosting one: take the primary's match "
               "(scene, config, a checkpoint), follow it tick by tick, check every tick's state hash, publish nothing "
               "to clients (docs/design/standby.md). --scene, --npcs and the match options are the primary's");
  app.add_option("--takeover-after-ticks", o.takeover_after_ticks,
                 "with --standby: take the match over when the primary has sent nothing for this many ticks (it then "
                 "hosts the match from the next tick; clients keep their ids and do not rejoin); 0 = never, only follow")
      ->check(CLI::Range(0u, 3000u));
  app.add_option("--trim-memory-every", o.trim_memory_s,
                 "every this many seconds, hand the memory malloc holds freed back to the system, on a thread of its "
                 "own (0 = never, else 0.1 to 86400): without it a long match's resident memory creeps up as clients "
                 "come and go")
      ->check(CLI::Range(0.0, MemoryTrimmer::kMaxSeconds));
  app.add_option("--summary-json", o.summary_json, "write the end-of-match summary to this JSON file");
  app.add_option("--log-format", o.log_format, "text, or json: one JSON object per line (time, level, match, msg)")
      ->check(CLI::IsMember({"text", "json"}));
  app.add_option("--log-dir", o.log_dir, "directory of the match log when --log is not given (<dir>/<match id>.tlog)");
  app.add_option("--log-level", o.log_level, "trace, debug, info, warn or error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}));

  ParseResult result;
  try {
    std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 parses a reversed vector
    app.parse(reversed);
    require_finite(o.duration_s, "--duration");
    require_finite(o.end_when_empty_s, "--end-when-empty");
    require_finite(o.end_when_routed_s, "--end-when-routed");
    require_finite(o.trim_memory_s, "--trim-memory-every");
    if (o.trim_memory_s > 0.0 && o.trim_memory_s < MemoryTrimmer::kMinSeconds)
      throw CLI::ValidationError("--trim-memory-every", fmt::format("0 (never) or at least {} s: a trim holds malloc's locks",
                                                                    MemoryTrimmer::kMinSeconds));
    if (o.standby && !o.listen.empty())
      throw CLI::ValidationError("--standby", "does not run over --listen (TCP) yet: use the primary's DDS domain");
    if (!o.public_address.empty() && o.listen.empty())
      throw CLI::ValidationError("--public-address", "needs --listen (it is the address of the TCP listener)");
    // Under Agones the sidecar's port comes from the environment, as in Agones's own SDKs.
    try {
      o.agones_port = agones_port_from_environment();
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError("AGONES_SDK_HTTP_PORT", e.what());
    }
    if (o.listen == kListenAgones && o.agones_port == 0)
      throw CLI::ValidationError("--listen", "agones needs AGONES_SDK_HTTP_PORT (set by Agones in the game server's pod)");
    require_finite(m.client_timeout_s, "--client-timeout");
    require_finite(m.interest.radius_m, "--interest-radius");
    require_finite(client_kbps, "--client-kbps");
    require_finite(m.player_speed_mps, "--player-speed");
    require_finite(m.npc_speed_mps, "--npc-speed");
    m.interest.budget_bytes = static_cast<std::uint32_t>(std::floor(client_kbps * 1000.0 / 8.0 / m.tick_hz));
    if (client_kbps > 0.0 && m.interest.budget_bytes < 128)
      throw CLI::ValidationError("--client-kbps", "leaves under 128 bytes per snapshot at this tick rate");
    m.interest.keepalive_ticks = m.tick_hz;
    if (no_log) o.log_file.clear();  // an unchanged object is refreshed once a second
  } catch (const CLI::ParseError& e) {
    result.exit_code = e.get_exit_code();
    result.message = e.get_name() == "CallForHelp" ? app.help() : std::string("throng-server: ") + e.what() + "\nRun with --help for the options.";
    if (e.get_name() == "CallForHelp") result.exit_code = 0;
    else if (result.exit_code == 0) result.exit_code = 2;
    return result;
  }
  result.options = o;
  return result;
}

}  // namespace throng::server
