// throng-replay: reads match logs written by throng-server (server/matchlog/FORMAT.md).
//   info    what is in a log (header, ticks, clients, size, torn tail or not)
//   verify  re-simulate from tick 1 and compare every tick's state hash
//   export  poses and push events of a tick range as CSV or JSON
//   play    re-publish the match over DDS at tick_hz x speed, so bots and viewers watch it as if live
//   seek    go to a tick through the nearest world keyframe and check its state hash
#include <cmath>
#include <cstdint>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "commands.h"
#include "throng/protocol/dds_transport.h"

int main(int argc, char** argv) {
  using namespace throng::replay;
  CLI::App app{
      "throng-replay: inspect, verify and export Throng match logs.\n"
      "Exit codes: 0 ok, 1 re-simulation diverged, 2 bad usage / unreadable or unsupported log,\n"
      "3 log damaged in the middle or ticks missing (handled up to there).\n"
      "Logs of format version 2 carry a world keyframe every ~2 s: seek and play --from start from the\n"
      "nearest one, verify compares each and runs keyframe-aligned segments in parallel (--jobs)."};
  app.require_subcommand(1);
  // CLI11's PositiveNumber prints its range as 0 to 1.8e308; ticks are whole numbers from 1.
  const CLI::Validator tick_number(
      [](std::string& v) -> std::string {
        std::uint64_t t = 0;
        try {
          std::size_t used = 0;
          t = std::stoull(v, &used);
          if (used != v.size() || v.front() == '-') return "a tick is a whole number from 1 (got '" + v + "')";
        } catch (const std::exception&) {
          return "a tick is a whole number from 1 (got '" + v + "')";
        }
        return t == 0 ? "ticks start at 1 (got 0)" : std::string();
      },
      "TICK>=1");

  InfoOptions info;
  CLI::App* info_cmd = app.add_subcommand("info", "Header, ticks, duration, clients, bytes/tick, index, torn tail or not");
  info_cmd->add_option("LOG", info.log, "match log file")->required();
  info_cmd->add_flag("--json", info.json, "machine-readable output");

  VerifyOptions verify;
  CLI::App* verify_cmd = app.add_subcommand(
      "verify", "Re-simulate from tick 1 feeding the logged inputs and compare every tick's state hash "
                "(exit 0 only if all match)");
  verify_cmd->add_option("LOG", verify.log, "match log file")->required();
  verify_cmd->add_flag("-q,--quiet", verify.quiet, "no progress on stderr");
  verify_cmd->add_flag("--exact-config", verify.exact_config,
                       "re-simulate with the logged interest settings and restore keyframes with their snapshot "
                       "baselines (default: a 1 cm interest radius, one snapshot thread, keyframes restored "
                       "without baselines, since snapshots are not part of the state hash; ~2x faster). Version 1 "
                       "keyframes (earlier builds' logs) always use the logged settings");
  verify_cmd->add_option("-j,--jobs", verify.jobs,
                         "threads: a log with keyframes is split into keyframe-aligned segments verified in parallel, "
                         "each from its logged keyframe (default: hardware threads)")
      ->check(CLI::Range(1u, 1024u));

  SeekOptions seek;
  CLI::App* seek_cmd = app.add_subcommand(
      "seek", "Re-simulate to --tick from the nearest world keyframe at or before it; print where it started, the "
              "time taken and the state hash at the tick against the logged one (exit 0 match, 1 mismatch)");
  seek_cmd->add_option("LOG", seek.log, "match log file")->required();
  seek_cmd->add_option("--tick", seek.tick, "the tick to go to (ticks start at 1)")->required()->check(tick_number);
  seek_cmd->add_flag("--json", seek.json, "machine-readable output");

  ExportOptions ex;
  CLI::App* export_cmd = app.add_subcommand(
      "export", "Re-simulate to --to and write poses (id, x, y, z, vx, vy, vz, yaw = facing in radians) and push events (a, b, depth, share_a, "
                "push) of ticks --from..--to");
  export_cmd->add_option("LOG", ex.log, "match log file")->required();
  export_cmd->add_option("--from", ex.from, "first tick to write (ticks start at 1)")->check(tick_number);
  export_cmd->add_option("--to", ex.to, "last tick to write (default: --from)");
  export_cmd->add_option("--format", ex.format, "csv or json")->check(CLI::IsMember({"csv", "json"}));
  export_cmd->add_option("--out", ex.out, "output file (default: stdout)");
  bool no_poses = false, no_pushes = false;
  export_cmd->add_flag("--no-poses", no_poses, "leave out poses");
  export_cmd->add_flag("--no-pushes", no_pushes, "leave out push events");
  export_cmd->add_flag("-q,--quiet", ex.quiet, "no progress on stderr");
  export_cmd->add_flag("--exact-config", ex.exact_config, "re-simulate with the logged interest settings");

  PlayOptions play;
  CLI::App* play_cmd = app.add_subcommand(
      "play",
      "Re-publish the logged match over DDS as throng-server did (match info, join/param replies, every logged "
      "client's snapshots on its own partition, stats), at tick_hz x --speed, so bots and viewers watch it as if "
      "live. Every tick's state hash is checked: a mismatch means this build does not reproduce the log (said "
      "loudly, exit 1; --strict stops there).\n"
      "WATCHERS: a client that joins is accepted as a SPECTATOR (the logged match takes no new inputs): it gets its "
      "own client id and partition ('w<n>') and follows an entity - the logged clients' entities in turn, or with no "
      "logged client connected the body nearest the centre of the battle - with snapshots built for it alone (logged "
      "interest settings, camera on that entity). Its commands are ignored and counted, parameter updates refused. "
      "Facing (yaw) in watcher snapshots is derived from velocity; positions are exact.\n"
      "SIGINT/SIGTERM: publishes match info 'ended', prints the summary, exits 0.");
  play_cmd->add_option("LOG", play.log, "match log file")->required();
  auto finite = [](const std::string& v) -> std::string {
    try {
      const double d = std::stod(v);
      return std::isfinite(d) ? std::string() : "must be a finite number";
    } catch (const std::exception&) {
      return "must be a number";
    }
  };
  play_cmd->add_option("--speed", play.speed, "playback speed, 0.1..16 (1 = as recorded)")
      ->check(CLI::Validator(finite, "FINITE"))
      ->check(CLI::Range(0.1, 16.0));
  play_cmd->add_option("--from", play.from, "first tick to publish (re-simulates up to it first; ticks start at 1)")
      ->check(tick_number);
  play_cmd->add_option("--domain", play.domain, "DDS domain id (like throng-server)")->check(CLI::Range(0, 231));
  play_cmd->add_flag("--network", play.network, "Fast DDS's default transports and discovery (default: 127.0.0.1 only)");
  play_cmd->add_option("--listen", play.listen, "udp://ADDR:PORT or tcp://ADDR:PORT: DDS on that one port only (viewers and bots use --server)")
      ->check(throng::protocol::check_endpoint);
  play_cmd->add_option("--security", play.security_dir,
                       "DDS Security: directory made by throng-pki; plays as the server identity (DIR/server)")
      ->check(CLI::ExistingDirectory);
  play_cmd->add_flag("--loop", play.loop, "at the end, seek back to --from and play again until SIGINT/SIGTERM");
  play_cmd->add_flag("--strict", play.strict, "stop at the first tick whose state hash differs from the log (exit 1)");
  play_cmd->add_option("--max-watchers", play.max_watchers, "spectators accepted at once (more: match_full)")
      ->check(CLI::Range(0u, 4096u));
  play_cmd->add_option("--watcher-timeout", play.watcher_timeout_s,
                       "drop a watcher that sent no command for this many seconds (0 = never)")
      ->check(CLI::Validator(finite, "FINITE"))
      ->check(CLI::Range(0.0, 86400.0));
  play_cmd->add_flag("-q,--quiet", play.quiet, "no progress line on stderr");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitBadInput;
  }
  try {
    if (*info_cmd) return run_info(info);
    if (*verify_cmd) return run_verify(verify);
    if (*seek_cmd) return run_seek(seek);
    if (*play_cmd) return run_play(play);
    ex.poses = !no_poses;
    ex.pushes = !no_pushes;
    return run_export(ex);
  } catch (const std::exception& e) {
    fmt::print(stderr, "throng-replay: {}\n", e.what());
    return kExitBadInput;
  }
}
