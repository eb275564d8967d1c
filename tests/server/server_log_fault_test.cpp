// The match log's disk fills up mid-match (a file-size limit set with prlimit: the kernel refuses
// writes past it with EFBIG, as a full disk refuses them with ENOSPC): the match keeps ticking to
// its end, the error is logged once with its cause and counted, /readyz says degraded, and the
// log on disk verifies up to its last complete block. What is lost: the log from that write on,
// nothing else.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <regex>
#include <string>
#include <thread>

#include "server_test_support.h"
#include "support/child_process.h"

namespace throng::test {
namespace {

using namespace std::chrono_literals;

const std::string kServer = std::string(THRONG_BIN_DIR) + "/throng-server";

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(ServerLogFault, AFullDiskEndsTheLogNotTheMatch) {
  if (!std::filesystem::exists("/usr/bin/prlimit")) GTEST_SKIP() << "no prlimit (util-linux)";
  TempDir dir("throng-logfull");
  const auto log = dir / "match.tlog";
  const auto summary = dir / "summary.json";
  // 60 kB: the header, the first ticks and a world keyframe fit; the limit is hit within seconds
  // (a 300-NPC battle logs ~0.5 kB a tick and ~27 kB per keyframe, every 2 s).
  constexpr std::uintmax_t kLimit = 60'000;
  ChildProcess server("/usr/bin/prlimit",
                      {"--fsize=" + std::to_string(kLimit), kServer, "--scene", "battle", "--npcs", "300", "--domain",
                       "197", "--admin-port", "0", "--duration", "8", "--log", log.string(), "--summary-json",
                       summary.string(), "--log-level", "info"},
                      dir / "out.txt", dir / "err.txt");
  const std::uint16_t port = wait_for_admin_port(dir / "err.txt");
  ASSERT_NE(port, 0) << read_file(dir / "err.txt");
  bool failed = false;
  for (auto deadline = std::chrono::steady_clock::now() + 30s; !failed && std::chrono::steady_clock::now() < deadline;
       std::this_thread::sleep_for(50ms)) {
    failed = read_file(dir / "err.txt").find("the match goes on without a log") != std::string::npos;
  }
  ASSERT_TRUE(failed) << "the log never reported its write error: " << read_file(dir / "err.txt");
  const std::string ready = http_get(port, "/readyz");
  EXPECT_NE(ready.find("200 OK"), std::string::npos) << ready;
  EXPECT_NE(ready.find("degraded: match log stopped: "), std::string::npos) << ready;
  EXPECT_NE(http_get(port, "/metrics").find("\nthrong_log_write_errors_total 1\n"), std::string::npos);

  // The match plays to its end and exits cleanly.
  EXPECT_EQ(server.wait(60s), 0) << read_file(dir / "err.txt");
  const std::string err = read_file(dir / "err.txt");
  EXPECT_EQ(count_of(err, "the match goes on without a log"), 1u) << err;
  EXPECT_NE(err.find("File too large"), std::string::npos) << "the cause is named: " << err;
  const auto j = nlohmann::json::parse(read_file(summary));
  EXPECT_GE(j["ticks"].get<std::uint64_t>(), 200u) << "the match stopped ticking";
  EXPECT_LE(std::filesystem::file_size(log), kLimit);

  // What reached the disk replays: every tick in it verifies.
  ChildProcess verify(std::string(THRONG_BIN_DIR) + "/throng-replay", {"verify", log.string()}, dir / "verify.txt",
                      dir / "verify.err");
  EXPECT_EQ(verify.wait(60s), 0) << read_file(dir / "verify.txt") << read_file(dir / "verify.err");
  const std::string report = read_file(dir / "verify.txt");
  EXPECT_NE(report.find("all state hashes"), std::string::npos) << report;
  const std::regex verified("verified ([0-9]+) ticks");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(report, m, verified)) << report;
  EXPECT_GE(std::stoul(m[1]), 30u) << report;
}

}  // namespace
}  // namespace throng::test
