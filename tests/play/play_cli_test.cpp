// throng-replay play refuses what it cannot play before opening DDS: exit 2 and one clear line.
#include <fstream>

#include <gtest/gtest.h>

#include "play_test_support.h"

namespace throng::play_test {
namespace {

TEST(PlayCli, BadInputIsExitTwoWithAMessage) {
  test::TempDir dir("throng-play-cli");
  const auto log = dir / "match.tlog";
  record_log(log, 60);
  const auto not_a_log = dir / "notes.txt";
  std::ofstream(not_a_log) << "this is not a match log\n";
  const std::string l = log.string();
  struct Case {
    std::vector<std::string> args;
    std::string expect;  // in stderr
  };
  const std::vector<Case> cases = {
      {{"play", (dir / "missing.tlog").string()}, "missing.tlog"},
      {{"play", not_a_log.string()}, "not a Throng match log"},
      {{"play", l, "--speed", "0"}, "--speed"},
      {{"play", l, "--speed", "20"}, "--speed"},
      {{"play", l, "--speed", "nan"}, "--speed"},
      {{"play", l, "--from", "0"}, "--from"},
      {{"play", l, "--from", "61"}, "--from 61 is outside the log: it can play ticks 1..60"},
      {{"play", l, "--domain", "400"}, "--domain"},
      {{"play", l, "--watcher-timeout", "-1"}, "--watcher-timeout"},
      {{"play"}, "LOG"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args.size() > 2 ? c.args[2] : c.args.back());
    test::ChildProcess p(kReplay, c.args, dir / "out.txt", dir / "err.txt");
    const auto code = p.wait(20s);
    ASSERT_TRUE(code.has_value()) << "still running after 20 s";
    EXPECT_EQ(*code, 2);
    const auto err = test::read_file(dir / "err.txt");
    EXPECT_NE(err.find(c.expect), std::string::npos) << err;
  }
  test::ChildProcess help(kReplay, {"play", "--help"}, dir / "help.txt", dir / "help.err");
  EXPECT_EQ(help.wait(10s), 0);
  const auto h = test::read_file(dir / "help.txt");
  EXPECT_NE(h.find("SPECTATOR"), std::string::npos) << "the help documents the watcher scheme: " << h;
}

}  // namespace
}  // namespace throng::play_test
