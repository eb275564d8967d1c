// throng-bench: runs scenes headless and measures speed and residual error.
//
//   throng-bench --scene crush --agents 50000 --ticks 300 --json
//   throng-bench --scene crush_post --agents 5000 --trace crush_post.csv
//   throng-bench --dump-scene street > street.json
//   throng-bench sweep --out sweep-out [--quick]
//
// Exit codes: 0 success, 2 bad command line or bad scene (the message names the flag or the JSON
// field), 1 a failure while running.
#include <iostream>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "report.h"
#include "run_scene.h"
#include "sweep.h"
#include "throng/geometry/contact_validation.h"
#include "throng/core/object_id.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"
#include "throng/scene/scene_json.h"

namespace {

constexpr int kExitBadInput = 2;

struct Cli {
  std::string scene = "crush";
  std::uint64_t agents = 0;
  std::uint64_t ticks = 0;
  std::uint32_t iterations = 0;
  std::string policy;
  std::string params;
  bool json = false;
  std::uint64_t warmup = 0;
  std::string dump;
  bool list = false;
  std::string sweep_out = "sweep-out";
  std::size_t validate_pairs = 100000;
  std::uint64_t validate_seed = 1;
  bool sweep_quick = false;
  std::uint64_t residual_from = 61;
  std::string trace;
  double carry = -1.0;  // < 0: the scene's blocked_motion_carry
  std::uint32_t threads = 1;
};

// The scene the flags describe: built-in or file, then --agents / --iterations / --policy / --params.
throng::scene::SceneDef scene_from_flags(const std::string& name, const Cli& c, const CLI::App& app) {
  auto def = throng::scene::load_scene(name);
  if (def.name.empty()) def.name = name;  // reports name the scene even when the file does not
  if (app.count("--agents")) def = throng::scene::scale_scene(def, c.agents);
  if (app.count("--iterations")) def.settings.iterations = c.iterations;
  if (app.count("--carry")) def.settings.blocked_motion_carry = c.carry;
  def.settings.threads = c.threads;
  if (!c.policy.empty()) def.policy = {c.policy, nullptr};
  if (!c.params.empty()) def.params = {c.params, nullptr};
  return def;
}

int run(const Cli& c, const CLI::App& app) {
  if (c.list) {
    for (const auto& n : throng::scene::builtin_scene_names()) fmt::print("{}\n", n);
    return 0;
  }
  if (!c.dump.empty()) {
    std::cout << throng::scene::scene_to_text(scene_from_flags(c.dump, c, app));
    return 0;
  }
  const auto def = scene_from_flags(c.scene, c, app);
  throng::bench::RunOptions options;
  options.ticks = app.count("--ticks") ? c.ticks : def.ticks;
  options.warmup = c.warmup;
  options.residual_from = c.residual_from;
  options.trace_path = c.trace;
  const auto result = throng::bench::run_scene(def, options);
  if (c.json)
    std::cout << throng::bench::to_json(result).dump() << "\n";
  else
    throng::bench::print_summary(stdout, result);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Cli c;
  CLI::App app{"throng-bench: run a crowd scene headless and report tick time and residual penetration"};
  app.add_option("--scene", c.scene, "built-in scene name or scene JSON file (built-ins: see --list-scenes)")
      ->capture_default_str();
  app.add_option("--agents", c.agents, "scale the scene to N bodies, keeping crowd density")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{throng::ObjectId::kMaxIndex}));
  app.add_option("--ticks", c.ticks, "measured ticks (default: the scene's)")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{100'000'000}));
  app.add_option("--iterations", c.iterations, "solver iterations per tick K (default: the scene's)")
      ->check(CLI::Range(1u, 256u));
  app.add_option("--policy", c.policy, "push policy JSON file (replaces the scene's)")->check(CLI::ExistingFile);
  app.add_option("--params", c.params, "parameter table JSON file (replaces the scene's)")->check(CLI::ExistingFile);
  app.add_flag("--json", c.json, "print exactly one JSON object on stdout instead of the summary");
  app.add_option("--warmup", c.warmup, "ticks run before the measured ones, left out of the timings")
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{100'000'000}));
  app.add_option("--carry", c.carry,
                 "blocked_motion_carry for this run (0: every agent steps its full speed into the jam every tick, as "
                 "in other engines; default: the scene's)")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--threads", c.threads,
                 "threads that sweep the crowd solve (the state hash is the same for any number)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 64u));
  app.add_option("--residual-from", c.residual_from,
                 "measure the residual every tick from this one (counted from 1, warm-up included) and report the "
                 "worst; 0 = only after the last tick")
      ->capture_default_str()
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{100'000'000}));
  app.add_option("--trace", c.trace, "write one CSV line per measured tick to FILE (tick, tick us, residual max/p99, ...)");
  app.add_option("--dump-scene", c.dump, "print scene NAME (built-in or file, --agents applied) as JSON and exit");
  app.add_flag("--list-scenes", c.list, "list the built-in scenes and exit");

  CLI::App* sweep = app.add_subcommand("sweep", "speed against error on crush: K sweep, N sweep, one_cell ratio");
  sweep->add_option("--out", c.sweep_out, "folder for sweep.json and sweep.svg")->capture_default_str();
  sweep->add_flag("--quick", c.sweep_quick, "few ticks and small N (CI smoke test)");
  CLI::App* validate = app.add_subcommand(
      "validate-contacts", "closed-form capsule contacts vs a long-double reference and FCL: error distributions");
  validate->add_option("--pairs", c.validate_pairs, "random capsule pairs (spread over all families)")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{8}, std::size_t{100000000}));
  validate->add_option("--seed", c.validate_seed, "random seed")->capture_default_str();
  app.require_subcommand(0, 1);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    fmt::print(stderr, "throng-bench: {}\nRun with --help for more information.\n", e.what());
    return kExitBadInput;
  }
  try {
    if (sweep->parsed()) return throng::bench::run_sweep(throng::bench::sweep_plan(c.sweep_quick), c.sweep_out);
    if (validate->parsed()) {
      std::cout << throng::geom::contact_validation_report(c.validate_pairs, c.validate_seed);
      return 0;
    }
    return run(c, app);
  } catch (const std::invalid_argument& e) {  // SceneError, ConfigError, bad settings
    fmt::print(stderr, "throng-bench: {}\n", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    fmt::print(stderr, "throng-bench: error: {}\n", e.what());
    return 1;
  }
}
