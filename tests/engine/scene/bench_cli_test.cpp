// End-to-end checks of the throng-bench command line: exit codes, --json shape, dump/reload, sweep.
// The bench binary sits next to this test binary (<build>/bin); builds without the bench
// (THRONG_BUILD_BENCH=OFF, e.g. the sanitizer build) skip these tests.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

namespace {

namespace fs = std::filesystem;

fs::path bench_binary() { return fs::read_symlink("/proc/self/exe").parent_path() / "throng-bench"; }

struct Result {
  int code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

// One folder per test process (ctest runs tests in parallel), removed by the fixture.
fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("throng-bench-test-" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

Result run(const std::string& args) {
  const fs::path err_file = temp_dir() / "stderr.txt";
  const std::string cmd = bench_binary().string() + " " + args + " 2>" + err_file.string();
  Result r;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int status = ::pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err_file);
  std::stringstream ss;
  ss << in.rdbuf();
  r.err = ss.str();
  return r;
}

class BenchCli : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(bench_binary())) GTEST_SKIP() << "throng-bench not built next to the tests";
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(temp_dir(), ignored);
  }
};

TEST_F(BenchCli, HelpExitsZero) {
  const auto r = run("--help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("--agents"), std::string::npos);
  EXPECT_EQ(run("sweep --help").code, 0);
}

TEST_F(BenchCli, BadFlagsExitTwo) {
  for (const char* args : {"--agents 0", "--ticks abc", "--iterations 999", "--no-such-flag", "--policy /nonexistent.json",
                           "--carry 1.5", "--carry nan", "--residual-from -1"}) {
    const auto r = run(args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_FALSE(r.err.empty()) << args;
  }
  const auto r = run("--scene no_such_scene");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("crush"), std::string::npos) << "lists the built-ins: " << r.err;
}

TEST_F(BenchCli, BadSceneFileExitsTwoNamingTheField) {
  const fs::path f = temp_dir() / "bad.json";
  std::ofstream(f) << R"({"spawns": [{"count": 1, "shape": {"type": "point", "centre": [0, 0]}},
                                     {"count": -4, "shape": {"type": "point", "centre": [0, 0]}}]})";
  const auto r = run("--scene " + f.string() + " --ticks 1");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("spawns[1].count: must be >= 0"), std::string::npos) << r.err;
}

TEST_F(BenchCli, JsonIsOneObjectWithTheReportedFields) {
  const auto r = run("--scene crush --agents 300 --ticks 5 --warmup 2 --iterations 3 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);  // throws if anything but one JSON document
  ASSERT_TRUE(j.is_object());
  EXPECT_EQ(j["agents"], 300);
  EXPECT_EQ(j["ticks"], 5);
  EXPECT_EQ(j["iterations"], 3);
  EXPECT_EQ(j["scene"], "crush");
  for (const char* k : {"median", "p95", "max"}) EXPECT_TRUE(j["tick_us"].contains(k)) << k;
  for (const char* k : {"max_pen_over_radius", "p99_pen_over_radius", "pairs_over_1pct"})
    EXPECT_TRUE(j["residual"].contains(k)) << k;
  for (const char* k : {"move", "broadphase", "solve"}) EXPECT_TRUE(j["phase_median_us"].contains(k)) << k;
  EXPECT_TRUE(j.contains("static_pen_max_over_radius"));
  EXPECT_EQ(j["nan_count"], 0);
  EXPECT_EQ(j["state_hash"].get<std::string>().size(), 16u);
}

// The worst tick, not the last: the residual measured every tick from --residual-from, and the
// same figures one CSV line per tick with --trace (whose worst line is the JSON's worst tick).
TEST_F(BenchCli, ResidualOverTimeAndTraceAgree) {
  const fs::path trace = temp_dir() / "trace.csv";
  const auto r = run("--scene " + std::string(THRONG_SOURCE_DIR) +
                     "/server/engine/data/scenes/crush_post.json --agents 400 --ticks 30 --residual-from 11 --carry 0 "
                     "--json --trace " + trace.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto& o = j["residual_over_time"];
  EXPECT_EQ(o["from_tick"], 11);
  EXPECT_EQ(o["ticks_measured"], 20);
  std::ifstream in(trace);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("tick,tick_us,max_pen_over_radius", 0), 0u) << line;
  double worst = -1.0;
  std::uint64_t worst_tick = 0, lines = 0, last_tick = 0, searched = 0;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string tick, tick_us, max_pen;
    std::getline(ss, tick, ',');
    std::getline(ss, tick_us, ',');
    std::getline(ss, max_pen, ',');
    // The rest: p99, pairs over 1%, solver pen, iterations, clamps, search_us, solve_us, searched,
    // second search, searched ahead.
    std::vector<std::string> rest;
    for (std::string field; std::getline(ss, field, ',');) rest.push_back(field);
    ASSERT_EQ(rest.size(), 10u) << line;
    EXPECT_GE(std::stod(rest[5]), 0.0) << line;
    EXPECT_GE(std::stod(rest[6]), 0.0) << line;
    EXPECT_TRUE(rest[7] == "0" || rest[7] == "1") << line;
    EXPECT_TRUE(rest[8] == "0" || rest[8] == "1") << line;
    EXPECT_TRUE(rest[9] == "0" || rest[9] == "1") << line;
    searched += rest[7] == "1";
    ++lines;
    last_tick = std::stoull(tick);
    if (std::stod(max_pen) > worst) {
      worst = std::stod(max_pen);
      worst_tick = last_tick;
    }
  }
  EXPECT_EQ(lines, 20u);
  EXPECT_GE(searched, 1u) << "carry 0 moves every body its full step: some tick must search";
  EXPECT_EQ(last_tick, 30u);
  EXPECT_EQ(o["worst_max_tick"], worst_tick);
  EXPECT_NEAR(o["worst_max_pen_over_radius"].get<double>(), worst, 1e-5 * std::max(1.0, worst));
  EXPECT_GE(o["worst_max_pen_over_radius"].get<double>(), j["residual"]["max_pen_over_radius"].get<double>())
      << "the last tick is one of the measured ones";
  EXPECT_GE(o["worst_p99_pen_over_radius"].get<double>(), j["residual"]["p99_pen_over_radius"].get<double>());

  const auto off = run("--scene crush --agents 300 --ticks 5 --residual-from 0 --json");
  ASSERT_EQ(off.code, 0) << off.err;
  EXPECT_EQ(nlohmann::json::parse(off.out)["residual_over_time"]["ticks_measured"], 0);
}

TEST_F(BenchCli, DumpedSceneRunsToTheSameHash) {
  const fs::path f = temp_dir() / "street.json";
  const auto dump = run("--dump-scene street --agents 300");
  ASSERT_EQ(dump.code, 0) << dump.err;
  std::ofstream(f) << dump.out;
  const auto a = run("--scene street --agents 300 --ticks 30 --json");
  const auto b = run("--scene " + f.string() + " --ticks 30 --json");
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_EQ(nlohmann::json::parse(a.out)["state_hash"], nlohmann::json::parse(b.out)["state_hash"]);
}

TEST_F(BenchCli, QuickSweepWritesJsonAndSvg) {
  const fs::path out = temp_dir() / "sweep";
  const auto r = run("sweep --quick --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("K=1"), std::string::npos);
  std::ifstream j(out / "sweep.json");
  const auto doc = nlohmann::json::parse(j);
  EXPECT_EQ(doc["k_sweep"].size(), 4u);
  EXPECT_GT(doc["one_cell"]["cost_ratio"].get<double>(), 0.0);
  std::ifstream svg(out / "sweep.svg");
  std::stringstream ss;
  ss << svg.rdbuf();
  EXPECT_EQ(ss.str().rfind("<svg", 0), 0u);
  EXPECT_NE(ss.str().find("</svg>"), std::string::npos);
}

}  // namespace
