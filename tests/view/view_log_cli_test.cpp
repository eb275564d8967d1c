// throng-view --log as a program: logs it cannot play are a clear error and exit 2 before any
// port is taken; bad log-mode options are usage errors (exit 1); a good log is served and the page
// protocol refuses live input and bad commands over the real WebSocket.
#include <gtest/gtest.h>
#include <signal.h>

#include <fstream>

#include "log_fixture.h"
#include "test_support.h"

namespace throng::view {
namespace {

using namespace testing;

const std::string kView = THRONG_BIN_DIR "/throng-view";

struct ViewRun {
  int code = -1;
  std::string out, err;
};

ViewRun run_view(const TempDir& dir, const std::vector<std::string>& args) {
  ChildProcess view(kView, args, dir / "out", dir / "err");
  const auto code = view.wait(30s);
  ViewRun r;
  if (!code) {
    view.kill_now();
    r.err = "(did not exit)";
    return r;
  }
  r.code = *code;
  r.out = read_file(dir / "out");
  r.err = read_file(dir / "err");
  return r;
}

TEST(ViewLogCli, HelpListsTheLogOptions) {
  TempDir dir;
  const ViewRun r = run_view(dir, {"--help"});
  EXPECT_EQ(r.code, 0);
  for (const char* opt : {"--log", "--speed", "--from", "--paused"}) EXPECT_NE(r.out.find(opt), std::string::npos) << opt;
}

TEST(ViewLogCli, MissingFileIsExit2) {
  TempDir dir;
  const ViewRun r = run_view(dir, {"--log", (dir / "nope.tlog").string(), "--port", "0"});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("cannot play"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nope.tlog"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("view at"), std::string::npos) << "served a page for a missing log";
}

TEST(ViewLogCli, NotALogIsExit2) {
  TempDir dir;
  std::ofstream(dir / "notes.txt") << "this is not a match log, just some text that is long enough to have a header\n";
  const ViewRun r = run_view(dir, {"--log", (dir / "notes.txt").string(), "--port", "0"});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("cannot play"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("view at"), std::string::npos);
}

TEST(ViewLogCli, TruncatedHeaderIsExit2) {
  TempDir dir;
  record_log(dir / "full.tlog", 60, 40);
  const std::string bytes = read_file(dir / "full.tlog");
  std::ofstream(dir / "cut.tlog", std::ios::binary) << bytes.substr(0, 40);
  const ViewRun r = run_view(dir, {"--log", (dir / "cut.tlog").string(), "--port", "0"});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("cannot play"), std::string::npos) << r.err;
}

TEST(ViewLogCli, FromBeyondTheEndIsExit2) {
  TempDir dir;
  record_log(dir / "m.tlog", 60, 40);
  const ViewRun r = run_view(dir, {"--log", (dir / "m.tlog").string(), "--port", "0", "--from", "61"});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--from 61 is beyond the log's last playable tick 60"), std::string::npos) << r.err;
}

TEST(ViewLogCli, BadSpeedAndLiveOnlyOptionsAreUsageErrors) {
  TempDir dir;
  record_log(dir / "m.tlog", 30, 40);
  const std::string log = (dir / "m.tlog").string();
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--log", log, "--speed", "0"}, {"--log", log, "--speed", "9"},
        {"--log", log, "--speed", "fast"}, {"--log", log, "--speed", "nan"}, {"--log", log, "--from", "-3"},
        {"--speed", "2"} /* without --log */, {"--log", log, "--domain", "5"}}) {
    const ViewRun r = run_view(dir, args);
    std::string joined;
    for (const auto& a : args) joined += a + " ";
    EXPECT_EQ(r.code, 1) << joined << "\n" << r.err << r.out;
    EXPECT_EQ(r.out.find("view at"), std::string::npos) << joined;
  }
}

// Reads until an error message with this reason arrives (frames are skipped).
bool got_error(WsClient& ws, const std::string& reason) {
  const auto until = Clock::now() + 5s;
  while (Clock::now() < until) {
    const auto m = ws.read(std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now()));
    if (m && m->find(R"("type":"error")") != std::string::npos) return m->find('"' + reason + '"') != std::string::npos;
  }
  return false;
}

TEST(ViewLogCli, ServesTheLogAndRefusesInputAndBadCommands) {
  TempDir dir;
  const RecordedLog rec = record_log(dir / "m.tlog", 90, 40);
  ChildProcess view(kView, {"--log", (dir / "m.tlog").string(), "--port", "0", "--paused", "--from", "30", "--quiet"},
                    dir / "view.out", dir / "view.err");
  std::optional<std::uint16_t> port;
  ASSERT_TRUE(wait_until([&] { return (port = view_port(dir / "view.out")).has_value(); }, 20s)) << read_file(dir / "view.err");
  EXPECT_NE(read_file(dir / "view.err").find("90 ticks at 30 Hz"), std::string::npos) << read_file(dir / "view.err");

  WsClient ws("127.0.0.1", *port, "/ws");
  const auto first = ws.read(10s);
  ASSERT_TRUE(first);
  const auto match = nlohmann::json::parse(*first);
  EXPECT_EQ(match["type"], "match");
  EXPECT_EQ(match["mode"], "replay");
  // Paused at --from: frames (the heartbeat) show tick 30, every body, the timeline.
  nlohmann::json frame;
  ASSERT_TRUE(wait_until(
      [&] {
        const auto m = ws.read(1s);
        if (!m || m->find(R"("type":"frame")") == std::string::npos) return false;
        frame = nlohmann::json::parse(*m);
        return true;
      },
      10s));
  EXPECT_EQ(frame["tick"], 30);
  EXPECT_EQ(frame["objects"].size(), 4 * rec.bodies);
  EXPECT_EQ(frame["replay"]["playing"], false);
  EXPECT_EQ(frame["replay"]["last_tick"], 90);
  EXPECT_EQ(frame["replay"]["hash_ok"], true);

  ws.send(R"({"type":"input","move_x":1,"move_y":0})");
  EXPECT_TRUE(got_error(ws, "unknown_type"));
  ws.send(R"({"type":"seek","tick":NaN})");
  EXPECT_TRUE(got_error(ws, "not_json"));
  ws.send(R"({"type":"seek","tick":"10"})");
  EXPECT_TRUE(got_error(ws, "bad_type"));
  ws.send(R"({"type":"speed","speed":100})");
  EXPECT_TRUE(got_error(ws, "out_of_range"));
  ws.send(R"({"type":"eject"})");
  EXPECT_TRUE(got_error(ws, "unknown_type"));
  // A good seek still works, clamped to the end.
  ws.send(R"({"type":"seek","tick":1e9})");
  ASSERT_TRUE(wait_until(
      [&] {
        const auto m = ws.read(1s);
        if (!m || m->find(R"("type":"frame")") == std::string::npos) return false;
        frame = nlohmann::json::parse(*m);
        return frame["tick"] == 90;
      },
      10s))
      << frame.dump().substr(0, 300);
  EXPECT_EQ(frame["input_errors_total"], 5);

  // A backwards seek: the "seeking" timeline goes out before the viewer blocks in it, then the
  // frame of the new tick.
  ws.send(R"({"type":"seek","tick":10})");
  bool saw_seeking = false;
  ASSERT_TRUE(wait_until(
      [&] {
        const auto m = ws.read(1s);
        if (!m) return false;
        const auto j = nlohmann::json::parse(*m);
        if (j["type"] == "timeline" && j["seeking"] == true && j["target"] == 10) saw_seeking = true;
        return j["type"] == "frame" && j["tick"] == 10;
      },
      10s));
  EXPECT_TRUE(saw_seeking) << "no seeking timeline before the frame of the seek";
  EXPECT_TRUE(wait_until([&] { return read_file(dir / "view.err").find("rejected") != std::string::npos; }, 5s))
      << read_file(dir / "view.err");

  view.signal(SIGTERM);
  const auto code = view.wait(15s);
  ASSERT_TRUE(code);
  EXPECT_EQ(*code, 0) << read_file(dir / "view.err");
}

}  // namespace
}  // namespace throng::view
