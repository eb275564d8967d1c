#include "sweep.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "run_scene.h"
#include "svg_plot.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"

namespace throng::bench {
namespace {

RunResult run_crush_like(const std::string& name, std::uint64_t agents, std::uint32_t iterations, const SweepPlan& plan) {
  scene::SceneDef def = scene::scale_scene(scene::builtin_scene(name), agents);
  def.settings.iterations = iterations;
  fmt::print(stderr, "sweep: {} N={} K={} ({} ticks)\n", name, agents, iterations, plan.ticks);
  RunOptions o;
  o.ticks = plan.ticks;
  o.residual_from = plan.residual_from;
  return run_scene(def, o);
}

void print_row(const std::string& key, const RunResult& r) {
  fmt::print("{:>10} {:>7} {:>4} {:>11.0f} {:>10.0f} {:>9.3f} {:>10.4g} {:>10.4g} {:>9} {:>11.4g} {:>11.4g}\n", key,
             r.agents, r.iterations, r.tick_us.median, r.tick_us.p95, r.us_per_agent(), r.residual.max_pen_over_radius,
             r.residual.p99_pen_over_radius, r.residual.pairs_over_1pct, r.residual_over_time.worst_max_pen_over_radius,
             r.residual_over_time.worst_p99_pen_over_radius);
}

void print_header(const std::string& title) {
  fmt::print("\n{}\n{:>10} {:>7} {:>4} {:>11} {:>10} {:>9} {:>10} {:>10} {:>9} {:>11} {:>11}\n", title, "", "N", "K",
             "median us", "p95 us", "us/agent", "max pen/r", "p99 pen/r", "pairs>1%", "worst max", "worst p99");
}

std::string plot(const std::vector<RunResult>& k_runs, const std::vector<RunResult>& n_runs, const RunResult& one_cell,
                 double one_cell_ratio, std::uint64_t ticks) {
  Panel err;
  err.title = fmt::format("Residual vs cost (crush, N={}, K labelled)", k_runs.empty() ? 0 : k_runs.front().agents);
  err.x_label = "median tick time [us]";
  err.y_label = "penetration / smaller radius (log)";
  err.log_y = true;
  err.x_from_zero = true;
  err.note = "last tick and worst tick (from the residual's first measured tick); a zero residual is drawn at the axis floor";
  Series mx{"max pen / r, last tick", "#c0392b", Marker::circle, true, {}};
  Series p99{"p99 pen / r, last tick", "#2471a3", Marker::square, true, {}};
  Series worst_mx{"max pen / r, worst tick", "#e67e22", Marker::diamond, true, {}};
  Series worst_p99{"p99 pen / r, worst tick", "#5dade2", Marker::diamond, true, {}};
  for (const auto& r : k_runs) {
    mx.points.push_back({r.tick_us.median, r.residual.max_pen_over_radius, fmt::format("K={}", r.iterations)});
    p99.points.push_back({r.tick_us.median, r.residual.p99_pen_over_radius, ""});
    worst_mx.points.push_back({r.tick_us.median, r.residual_over_time.worst_max_pen_over_radius, ""});
    worst_p99.points.push_back({r.tick_us.median, r.residual_over_time.worst_p99_pen_over_radius, ""});
  }
  err.series = {mx, p99, worst_mx, worst_p99};

  Panel cost;
  cost.title = fmt::format("Cost per agent vs N (crush, K={})", n_runs.empty() ? 0 : n_runs.front().iterations);
  cost.x_label = "agents N (log)";
  cost.y_label = "median tick time per agent [us]";
  cost.log_x = true;
  cost.y_from_zero = true;
  // one_cell is a note, not a point: its cost per agent comes from another regime (pile relief),
  // and as a point it would distort the curve whose shape (flat = O(N)) is the point of this panel.
  cost.note = fmt::format("flat = linear scaling. one_cell (all start at one point), N={}: {:.3f} us/agent = {:.1f}x uniform",
                          one_cell.agents, one_cell.us_per_agent(), one_cell_ratio);
  Series uni{"crush (uniform disk)", "#1e8449", Marker::circle, true, {}};
  for (const auto& r : n_runs) uni.points.push_back({double(r.agents), r.us_per_agent(), fmt::format("{:.2f}", r.us_per_agent())});
  cost.series = {uni};
  return render_svg(fmt::format("throng crush sweep ({} ticks per run)", ticks), {err, cost});
}

void write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace

SweepPlan sweep_plan(bool quick) {
  SweepPlan p;
  if (!quick) {
    p.iterations = {1, 2, 3, 4, 6, 8, 12, 16};
    p.agents = {1'000, 2'000, 5'000, 10'000, 20'000, 50'000, 100'000};
    p.ticks = scene::builtin_scene("crush").ticks;
    return p;
  }
  p.iterations = {1, 2, 4, 8};
  p.k_agents = 2'000;
  p.agents = {500, 1'000, 2'000};
  p.ticks = 20;
  p.one_cell_agents = 2'000;
  p.residual_from = 10;
  return p;
}

int run_sweep(const SweepPlan& plan, const std::string& out_dir) {
  const std::uint32_t default_k = scene::builtin_scene("crush").settings.iterations;
  std::vector<RunResult> k_runs, n_runs;
  for (const std::uint32_t k : plan.iterations) k_runs.push_back(run_crush_like("crush", plan.k_agents, k, plan));
  for (const std::uint64_t n : plan.agents) n_runs.push_back(run_crush_like("crush", n, default_k, plan));
  const RunResult heap = run_crush_like("one_cell", plan.one_cell_agents, default_k, plan);
  const RunResult* uniform = nullptr;
  for (const auto& r : n_runs)
    if (r.agents == plan.one_cell_agents) uniform = &r;
  const double ratio = uniform && uniform->us_per_agent() > 0.0 ? heap.us_per_agent() / uniform->us_per_agent() : 0.0;

  fmt::print("crush sweep, {} ticks per run (pen/r after the last tick; worst: the largest over ticks {}..{})\n", plan.ticks,
             plan.residual_from, plan.ticks);
  print_header("iterations K at fixed N");
  for (const auto& r : k_runs) print_row(fmt::format("K={}", r.iterations), r);
  print_header("agents N at the default K");
  for (const auto& r : n_runs) print_row(fmt::format("N={}", r.agents), r);
  print_header("one_cell vs uniform at the same N and K");
  if (uniform) print_row("uniform", *uniform);
  print_row("one_cell", heap);
  fmt::print("cost per agent one_cell / uniform = {:.2f}\n", ratio);

  nlohmann::ordered_json j;
  j["scene"] = "crush";
  j["ticks"] = plan.ticks;
  j["default_iterations"] = default_k;
  j["k_sweep"] = nlohmann::ordered_json::array();
  for (const auto& r : k_runs) j["k_sweep"].push_back(to_json(r));
  j["n_sweep"] = nlohmann::ordered_json::array();
  for (const auto& r : n_runs) j["n_sweep"].push_back(to_json(r));
  j["one_cell"] = {{"run", to_json(heap)},
                   {"uniform_us_per_agent", uniform ? uniform->us_per_agent() : 0.0},
                   {"one_cell_us_per_agent", heap.us_per_agent()},
                   {"cost_ratio", ratio}};

  std::filesystem::create_directories(out_dir);
  const auto json_path = std::filesystem::path(out_dir) / "sweep.json";
  const auto svg_path = std::filesystem::path(out_dir) / "sweep.svg";
  write_file(json_path, j.dump(2) + "\n");
  write_file(svg_path, plot(k_runs, n_runs, heap, ratio, plan.ticks));
  fmt::print(stderr, "sweep: wrote {} and {}\n", json_path.string(), svg_path.string());
  return 0;
}

}  // namespace throng::bench
