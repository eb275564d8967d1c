// throng-view as a program: --help, no server, a port in use, and bad page input over the real
// WebSocket (counted, answered with an error, never forwarded to the server).
#include <gtest/gtest.h>
#include <signal.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

#include "test_support.h"

namespace throng::view {
namespace {

using namespace testing;

const std::string kServer = THRONG_BIN_DIR "/throng-server";
const std::string kView = THRONG_BIN_DIR "/throng-view";


TEST(ViewCli, HelpDescribesTheOptions) {
  TempDir dir;
  ChildProcess view(kView, {"--help"}, dir / "out", dir / "err");
  const auto code = view.wait(10s);
  ASSERT_TRUE(code);
  EXPECT_EQ(*code, 0);
  const std::string out = read_file(dir / "out");
  for (const char* opt : {"--domain", "--port", "--bind", "--name", "--server-wait", "--web-root"})
    EXPECT_NE(out.find(opt), std::string::npos) << opt;
}

TEST(ViewCli, NoServerIsAClearErrorAndExit2) {
  TempDir dir;
  ChildProcess view(kView, {"--domain", "206", "--port", "0", "--server-wait", "1"}, dir / "out", dir / "err");
  const auto code = view.wait(20s);
  ASSERT_TRUE(code) << "throng-view did not give up";
  EXPECT_EQ(*code, 2);
  EXPECT_NE(read_file(dir / "err").find("no server on domain 206 within 1 s"), std::string::npos) << read_file(dir / "err");
}

TEST(ViewCli, PortInUseIsAClearErrorAndExit1) {
  boost::asio::io_context io;
  boost::asio::ip::tcp::acceptor busy(io, {boost::asio::ip::make_address("127.0.0.1"), 0});
  const auto port = busy.local_endpoint().port();
  TempDir dir;
  ChildProcess view(kView, {"--domain", "206", "--port", std::to_string(port)}, dir / "out", dir / "err");
  const auto code = view.wait(10s);
  ASSERT_TRUE(code);
  EXPECT_EQ(*code, 1);
  EXPECT_NE(read_file(dir / "err").find("cannot listen on 127.0.0.1:" + std::to_string(port) + ": address in use"),
            std::string::npos)
      << read_file(dir / "err");
}

// Reads until an error message with this reason arrives (frames and the match are skipped).
bool got_error(WsClient& ws, const std::string& reason) {
  const auto until = Clock::now() + 5s;
  while (Clock::now() < until) {
    const auto m = ws.read(std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now()));
    if (m && m->find(R"("type":"error")") != std::string::npos) return m->find('"' + reason + '"') != std::string::npos;
  }
  return false;
}

TEST(ViewCli, BadPageInputIsRejectedAndNeverForwarded) {
  constexpr int kDomain = 204;
  TempDir dir;
  ChildProcess server(kServer,
                      {"--no-log", "--scene", "battle", "--npcs", "200", "--domain", std::to_string(kDomain), "--admin-port", "-1",
                       "--duration", "60", "--summary-json", (dir / "summary.json").string(), "--client-timeout", "60",
                       "--log-level", "warn"},
                      dir / "server.out", dir / "server.log");
  ChildProcess view(kView, {"--domain", std::to_string(kDomain), "--port", "0", "--name", "view-bad-input", "--quiet"},
                    dir / "view.out", dir / "view.err");
  std::optional<std::uint16_t> port;
  ASSERT_TRUE(wait_until([&] { return (port = view_port(dir / "view.out")).has_value(); }, 20s)) << read_file(dir / "view.err");
  ASSERT_TRUE(wait_until([&] { return read_file(dir / "view.err").find("joined as client") != std::string::npos; }, 30s))
      << read_file(dir / "view.err");

  WsClient ws("127.0.0.1", *port, "/ws");
  const auto first = ws.read(10s);
  ASSERT_TRUE(first);
  EXPECT_NE(first->find(R"("type":"match")"), std::string::npos) << "the match comes first: " << first->substr(0, 200);

  ws.send("not json at all");
  EXPECT_TRUE(got_error(ws, "not_json"));
  ws.send(R"({"type":"input","move_x":1e400})");
  EXPECT_TRUE(got_error(ws, "not_json"));
  ws.send(R"({"type":"input","move_x":1e300,"move_y":0})");
  EXPECT_TRUE(got_error(ws, "out_of_range"));
  ws.send(R"({"type":"input","facing":1e9})");
  EXPECT_TRUE(got_error(ws, "out_of_range"));
  ws.send(R"({"type":"input","camera_x":99999999,"camera_y":0})");
  EXPECT_TRUE(got_error(ws, "out_of_range"));
  ws.send(R"({"type":"input","actions":255})");
  EXPECT_TRUE(got_error(ws, "bad_actions"));
  ws.send(R"({"type":"input","move_x":"fast"})");
  EXPECT_TRUE(got_error(ws, "bad_type"));
  ws.send("\x01\x02", /*binary=*/true);
  EXPECT_TRUE(got_error(ws, "not_text"));
  ws.send(R"({"type":"input","move_x":0.5,"move_y":0})");  // a good one in between keeps working

  // The frames count them, and say when the server has applied one of the gateway's commands
  // (applied_seq): only then can the server's summary show accepted commands for this client.
  bool counted = false, applied = false;
  const auto until = Clock::now() + 5s;
  while (!(counted && applied) && Clock::now() < until) {
    const auto m = ws.read(1s);
    if (!m || m->find(R"("type":"frame")") == std::string::npos) continue;
    const auto f = nlohmann::json::parse(*m);
    counted = f["input_errors_total"] == 8 && f["input_errors"]["out_of_range"] == 3;
    applied = f.value("applied_seq", 0u) > 0;
  }
  EXPECT_TRUE(counted);
  EXPECT_TRUE(applied) << "no command of the gateway was applied by the server within 5 s";
  // The loop logs after it broadcast the frame that counted them: wait for the line.
  EXPECT_TRUE(wait_until([&] { return read_file(dir / "view.err").find("rejected") != std::string::npos; }, 5s))
      << read_file(dir / "view.err");

  view.signal(SIGINT);
  const auto code = view.wait(15s);
  ASSERT_TRUE(code);
  EXPECT_EQ(*code, 0) << read_file(dir / "view.err");
  server.signal(SIGINT);
  ASSERT_TRUE(server.wait(30s));
  const auto summary = nlohmann::json::parse(read_file(dir / "summary.json"), nullptr, false);
  ASSERT_FALSE(summary.is_discarded()) << read_file(dir / "server.log");
  bool found = false;
  for (const auto& c : summary["clients"]) {
    if (c.value("name", "") != "view-bad-input") continue;
    found = true;
    EXPECT_GT(c["commands_accepted"].get<std::uint64_t>(), 0u) << c.dump();
    EXPECT_EQ(c["commands_rejected"].get<std::uint64_t>(), 0u) << "bad page input reached the server: " << c.dump();
    EXPECT_EQ(c["departure"], "left") << c.dump();
  }
  EXPECT_TRUE(found) << summary.dump(2);
}

}  // namespace
}  // namespace throng::view
