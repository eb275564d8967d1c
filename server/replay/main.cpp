// throng-replay: reads match logs written by throng-server (server/matchlog/FORMAT.md).
//   info    what is in a log (header, ticks, clients, size, torn tail or not)
//   verify  re-simulate from tick 1 and compare every tick's state hash
//   export  poses and push events of a tick range as CSV or JSON
//   seek    go to a tick through the nearest world keyframe and check its state hash
// Not yet in this file: `play` (re-publishing over DDS).
#include <exception>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "commands.h"

int main(int argc, char** argv) {
  using namespace throng::replay;
  CLI::App app{
      "throng-replay: inspect, verify and export Throng match logs.\n"
      "Exit codes: 0 ok, 1 re-simulation diverged, 2 bad usage / unreadable or unsupported log,\n"
      "3 log damaged in the middle or ticks missing (handled up to there).\n"
      "Logs of format version 2 carry a world keyframe every ~2 s: seek starts from the nearest one,\n"
      "verify compares each and runs keyframe-aligned segments in parallel (--jobs)."};
  app.require_subcommand(1);

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
                       "re-simulate with the logged interest settings (default: a 1 cm interest radius, since "
                       "snapshots are not part of the state hash; ~2x faster). Logs with keyframes always use the "
                       "logged settings (a checkpoint restores only into the logged config)");
  verify_cmd->add_option("-j,--jobs", verify.jobs,
                         "threads: a log with keyframes is split into keyframe-aligned segments verified in parallel, "
                         "each from its logged keyframe (default: hardware threads)")
      ->check(CLI::Range(1u, 1024u));

  SeekOptions seek;
  CLI::App* seek_cmd = app.add_subcommand(
      "seek", "Re-simulate to --tick from the nearest world keyframe at or before it; print where it started, the "
              "time taken and the state hash at the tick against the logged one (exit 0 match, 1 mismatch)");
  seek_cmd->add_option("LOG", seek.log, "match log file")->required();
  seek_cmd->add_option("--tick", seek.tick, "the tick to go to (ticks start at 1)")->required()->check(CLI::PositiveNumber);
  seek_cmd->add_flag("--json", seek.json, "machine-readable output");

  ExportOptions ex;
  CLI::App* export_cmd = app.add_subcommand(
      "export", "Re-simulate to --to and write poses (id, x, y, z, vx, vy, vz) and push events (a, b, depth, share_a, "
                "push) of ticks --from..--to");
  export_cmd->add_option("LOG", ex.log, "match log file")->required();
  export_cmd->add_option("--from", ex.from, "first tick to write (ticks start at 1)")->check(CLI::PositiveNumber);
  export_cmd->add_option("--to", ex.to, "last tick to write (default: --from)");
  export_cmd->add_option("--format", ex.format, "csv or json")->check(CLI::IsMember({"csv", "json"}));
  export_cmd->add_option("--out", ex.out, "output file (default: stdout)");
  bool no_poses = false, no_pushes = false;
  export_cmd->add_flag("--no-poses", no_poses, "leave out poses");
  export_cmd->add_flag("--no-pushes", no_pushes, "leave out push events");
  export_cmd->add_flag("-q,--quiet", ex.quiet, "no progress on stderr");
  export_cmd->add_flag("--exact-config", ex.exact_config, "re-simulate with the logged interest settings");

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
    ex.poses = !no_poses;
    ex.pushes = !no_pushes;
    return run_export(ex);
  } catch (const std::exception& e) {
    fmt::print(stderr, "throng-replay: {}\n", e.what());
    return kExitBadInput;
  }
}
