// throng-replay as a user runs it: exit codes and what it prints.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "matchlog_test_util.h"
#include "throng/matchlog/log_player.h"

namespace throng::matchlog {
namespace {

struct CliRun {
  int code = -1;
  std::string out, err;
};

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

CliRun run(const std::string& args, const std::filesystem::path& dir) {
  const std::string bin = std::string(THRONG_BIN_DIR) + "/throng-replay";
  const std::string cmd = "'" + bin + "' " + args + " > '" + (dir / "out.txt").string() + "' 2> '" + (dir / "err.txt").string() + "'";
  const int status = std::system(cmd.c_str());
  CliRun r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(dir / "out.txt");
  r.err = slurp(dir / "err.txt");
  return r;
}

bool has(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

class ReplayCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { played_ = new test::PlayedMatch(test::play_match(90)); }
  static void TearDownTestSuite() { delete played_; }
  void SetUp() override {
    if (!std::filesystem::exists(std::string(THRONG_BIN_DIR) + "/throng-replay")) GTEST_SKIP() << "throng-replay not built";
    dir_ = test::test_dir();
    log_ = dir_ / "m.tlog";
    test::write_played(log_, played_->ticks, test::match_header());
  }
  static test::PlayedMatch* played_;
  std::filesystem::path dir_, log_;
};
test::PlayedMatch* ReplayCli::played_ = nullptr;

TEST_F(ReplayCli, HelpEverywhere) {
  for (const char* sub : {"", "info ", "verify ", "export ", "seek "}) {
    const CliRun r = run(std::string(sub) + "--help", dir_);
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_TRUE(has(r.out, "Usage")) << sub << r.out;
  }
  EXPECT_EQ(run("", dir_).code, 2);  // a subcommand is required
  EXPECT_EQ(run("frobnicate", dir_).code, 2);
}

TEST_F(ReplayCli, InfoAndVerifyOnACleanLog) {
  CliRun r = run("info '" + log_.string() + "'", dir_);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "1..90 (90 ticks, 3.0 s of play)")) << r.out;
  EXPECT_TRUE(has(r.out, "from 7 clients")) << r.out;  // six bots and the refused late joiner
  EXPECT_TRUE(has(r.out, "shutdown began before tick 90")) << r.out;
  EXPECT_TRUE(has(r.out, "closed cleanly")) << r.out;
  EXPECT_TRUE(has(r.out, "bytes/tick")) << r.out;

  r = run("info --json '" + log_.string() + "'", dir_);
  EXPECT_EQ(r.code, 0);
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("ticks"), 90);
  EXPECT_EQ(j.at("torn_tail"), false);
  EXPECT_EQ(j.at("match_id"), "recorded");
  EXPECT_EQ(j.at("keyframes"), 0);

  r = run("verify '" + log_.string() + "'", dir_);
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_TRUE(has(r.out, "verified 90 ticks (1..90): all state hashes match")) << r.out;
  EXPECT_TRUE(has(r.out, "x real time at 30 Hz")) << r.out;
  EXPECT_TRUE(has(r.err, "verify")) << r.err;  // progress on stderr
}

TEST_F(ReplayCli, VerifyFailsOnATamperedHash) {
  const auto bad = dir_ / "tampered.tlog";
  test::write_played(bad, played_->ticks, test::match_header(), {}, 33);
  const CliRun r = run("verify -q '" + bad.string() + "'", dir_);
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "MISMATCH at tick 33")) << r.out;
  EXPECT_TRUE(has(r.out, "ticks 1..32 matched")) << r.out;
  EXPECT_FALSE(has(r.err, "ticks/s")) << r.err;  // -q: no progress
}

TEST_F(ReplayCli, TornCorruptAndForeignFiles) {
  const auto bytes = test::read_bytes(log_);
  const auto torn = dir_ / "torn.tlog";
  test::write_bytes(torn, bytes, bytes.size() - 100);
  CliRun r = run("info '" + torn.string() + "'", dir_);
  EXPECT_EQ(r.code, 0);
  EXPECT_TRUE(has(r.out, "TORN TAIL: log ends mid-record at byte")) << r.out;
  r = run("verify -q '" + torn.string() + "'", dir_);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "all state hashes match")) << r.out;
  EXPECT_TRUE(has(r.out, "torn tail")) << r.out;

  auto flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x40;
  const auto corrupt = dir_ / "corrupt.tlog";
  test::write_bytes(corrupt, flipped, flipped.size());
  r = run("info '" + corrupt.string() + "'", dir_);
  EXPECT_EQ(r.code, 3);
  EXPECT_TRUE(has(r.out, "CORRUPT: corrupt record at byte")) << r.out;
  r = run("verify -q '" + corrupt.string() + "'", dir_);
  EXPECT_EQ(r.code, 3);
  EXPECT_TRUE(has(r.out, "LOG DAMAGED")) << r.out;

  const auto foreign = dir_ / "foreign.txt";
  test::write_bytes(foreign, std::vector<std::uint8_t>(100, 'a'), 100);
  r = run("info '" + foreign.string() + "'", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r.err, "not a Throng match log")) << r.err;
  r = run("verify '" + (dir_ / "missing.tlog").string() + "'", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r.err, "cannot open")) << r.err;
}

TEST_F(ReplayCli, ExportCsvAndJson) {
  const auto csv = dir_ / "poses.csv";
  CliRun r = run("export -q '" + log_.string() + "' --from 10 --to 12 --format csv --out '" + csv.string() + "'", dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "record,tick,id,x,y,z,vx,vy,vz,yaw,other_id,depth_m,share_a,push_m");
  std::size_t poses = 0, pushes = 0;
  std::set<std::string> ticks;
  while (std::getline(in, line)) {
    if (line.rfind("pose,", 0) == 0) ++poses;
    else if (line.rfind("push,", 0) == 0) ++pushes;
    else ADD_FAILURE() << line;
    ticks.insert(line.substr(5, 2));
  }
  EXPECT_EQ(poses, 3u * test::small_battle().agent_count());
  EXPECT_GT(pushes, 0u);
  EXPECT_EQ(ticks, (std::set<std::string>{"10", "11", "12"}));

  const auto json = dir_ / "poses.json";
  r = run("export -q '" + log_.string() + "' --from 5 --to 6 --format json --no-pushes --out '" + json.string() + "'", dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(json));
  ASSERT_EQ(j.at("ticks").size(), 2u);
  EXPECT_EQ(j.at("ticks")[0].at("tick"), 5);
  EXPECT_EQ(j.at("ticks")[0].at("poses").size(), test::small_battle().agent_count());
  EXPECT_EQ(j.at("ticks")[0].at("poses")[0].size(), 8u);
  EXPECT_EQ(j.at("pose_fields").back(), "yaw");
  EXPECT_FALSE(j.at("ticks")[0].contains("pushes"));

  r = run("export -q '" + log_.string() + "' --from 80 --to 95", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r.err, "past the last tick")) << r.err;
  r = run("export -q '" + log_.string() + "' --from 3 --format xml", dir_);
  EXPECT_EQ(r.code, 2);
}

TEST_F(ReplayCli, KeyframesInfoSeekAndParallelVerify) {
  const auto kf = dir_ / "kf.tlog";
  test::write_played(kf, played_->ticks, test::match_header(), {}, 0, &played_->keyframes);  // one keyframe: tick 60
  CliRun r = run("info '" + kf.string() + "'", dir_);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "format     version 3")) << r.out;
  EXPECT_TRUE(has(r.out, "keyframes  1 world keyframes, every 60 ticks (ticks 60..60)")) << r.out;
  r = run("info --json '" + kf.string() + "'", dir_);
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("keyframes"), 1);
  EXPECT_EQ(j.at("keyframe_interval_ticks"), 60);
  EXPECT_GT(j.at("keyframe_bytes").get<std::uint64_t>(), 0u);

  r = run("seek '" + kf.string() + "' --tick 75", dir_);
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_TRUE(has(r.out, "seeked to tick 75 from the keyframe of tick 60 (15 ticks re-simulated)")) << r.out;
  EXPECT_TRUE(has(r.out, ": match")) << r.out;
  r = run("seek --json '" + kf.string() + "' --tick 59", dir_);
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("tick"), 59);
  EXPECT_EQ(j.at("keyframe_tick"), 0);  // before the first keyframe: from the match start
  EXPECT_EQ(j.at("ticks_simulated"), 59);
  EXPECT_EQ(j.at("match"), true);
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(played_->ticks[58].state_hash));
  EXPECT_EQ(j.at("state_hash"), std::string(hex));

  r = run("verify -q --jobs 2 '" + kf.string() + "'", dir_);
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_TRUE(has(r.out, "all state hashes and keyframes match")) << r.out;
  EXPECT_TRUE(has(r.out, "2 jobs, 2 segments, 1 keyframes compared")) << r.out;
}

TEST_F(ReplayCli, SeekMismatchAndErrors) {
  const auto bad = dir_ / "tampered_kf.tlog";
  test::write_played(bad, played_->ticks, test::match_header(), {}, 70, &played_->keyframes);
  CliRun r = run("seek '" + bad.string() + "' --tick 70", dir_);
  EXPECT_EQ(r.code, 1) << r.out << r.err;
  EXPECT_TRUE(has(r.out, "MISMATCH")) << r.out;
  r = run("verify -q '" + bad.string() + "'", dir_);
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "MISMATCH at tick 70")) << r.out;
  // 90 ticks, one keyframe (60): none after the divergent tick to compare the world with, and it says so.
  EXPECT_TRUE(has(r.out, "Objects: no logged keyframe at or after tick 70")) << r.out;

  r = run("seek '" + log_.string() + "' --tick 91", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r.err, "--tick 91 is outside the ticks that can be re-simulated (1..90)")) << r.err;
  r = run("seek '" + log_.string() + "' --tick 0", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r.err, "ticks start at 1 (got 0)")) << r.err;
  r = run("seek '" + log_.string() + "' --tick 1.5", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r.err, "a tick is a whole number from 1 (got '1.5')")) << r.err;
  r = run("export '" + log_.string() + "' --from -3", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r.err, "a tick is a whole number from 1")) << r.err;
  r = run("seek '" + log_.string() + "'", dir_);  // --tick is required
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r.err, "--tick")) << r.err;
  r = run("seek '" + (dir_ / "missing.tlog").string() + "' --tick 3", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r.err, "cannot open")) << r.err;
  r = run("verify --jobs 0 '" + log_.string() + "'", dir_);
  EXPECT_EQ(r.code, 2);
  // A log without keyframes seeks from the match start.
  r = run("seek '" + log_.string() + "' --tick 40", dir_);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "from the match start (40 ticks re-simulated)")) << r.out;
}

TEST_F(ReplayCli, ExportStartsFromTheKeyframeBeforeFromWithTheSameOutput) {
  // The same ticks exported from a log with a keyframe at tick 60 (restored without its snapshot
  // baselines) and from one without keyframes (re-simulated from tick 1): identical bytes.
  const auto kf = dir_ / "kf.tlog";
  test::write_played(kf, played_->ticks, test::match_header(), {}, 0, &played_->keyframes);
  for (const char* format : {"csv", "json"}) {
    const auto a = dir_ / (std::string("from_start.") + format), b = dir_ / (std::string("from_keyframe.") + format);
    ASSERT_EQ(run("export -q '" + log_.string() + "' --from 70 --to 74 --format " + format + " --out '" + a.string() + "'", dir_).code, 0);
    const CliRun r = run("export '" + kf.string() + "' --from 70 --to 74 --format " + format + " --out '" + b.string() + "'", dir_);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(has(r.err, "re-simulating from the keyframe of tick 60")) << r.err;
    const auto bytes = test::read_bytes(a);
    EXPECT_GT(bytes.size(), 1000u);
    EXPECT_EQ(bytes, test::read_bytes(b)) << format;
  }
}

TEST_F(ReplayCli, ExportYawIsTheFacing) {
  // The facing of a client's entity is its last command's facing_rad; snapshots carry it unquantized
  // as entity_yaw. NPCs face where the AI turned them.
  const auto json = dir_ / "yaw.json";
  const CliRun r = run("export -q '" + log_.string() + "' --from 40 --to 41 --format json --no-pushes --out '" + json.string() + "'", dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(json));
  std::map<std::uint32_t, float> yaw;
  std::size_t turned = 0;
  for (const auto& p : j.at("ticks")[1].at("poses")) {
    const float y = p.at(7).get<float>();
    EXPECT_LE(std::abs(y), 3.1416f);
    yaw[p.at(0).get<std::uint32_t>()] = y;
    if (y != 0.0f) ++turned;
  }
  EXPECT_GT(turned, yaw.size() / 2);
  LogPlayer player(log_.string());
  player.seek(41);
  ASSERT_EQ(player.outbox().snapshot_count, 6u);
  for (std::size_t i = 0; i < player.outbox().snapshot_count; ++i) {
    const auto& s = player.outbox().snapshots[i];
    ASSERT_EQ(yaw.count(s.entity), 1u);
    EXPECT_EQ(yaw[s.entity], s.entity_yaw) << "client " << s.client_id;
  }
  // CSV: the same column.
  const auto csv = dir_ / "yaw.csv";
  ASSERT_EQ(run("export -q '" + log_.string() + "' --from 41 --format csv --no-pushes --out '" + csv.string() + "'", dir_).code, 0);
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::size_t rows = 0;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    ASSERT_GE(f.size(), 10u) << line;
    EXPECT_FLOAT_EQ(std::stof(f[9]), yaw[static_cast<std::uint32_t>(std::stoul(f[2]))]) << line;
    ++rows;
  }
  EXPECT_EQ(rows, yaw.size());
}

}  // namespace
}  // namespace throng::matchlog
