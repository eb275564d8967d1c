// End to end: throng-server + throng-view + headless Chromium (Debian's /usr/bin/chromium, driven
// over the DevTools protocol with a Beast WebSocket client). The page must draw every character it
// reports in view, a held key must move the controlled entity on the server (the position comes
// from the server's snapshots; the page does no prediction), the collision overlay (C) must draw
// contact planes for the pairs the server reports near the camera with the server's push ratios
// (read here too, from the server's contacts topic in the viewer's partition), and the test keeps a screenshot as
// <build>/artifacts/view_e2e.png (THRONG_UPDATE_SCREENSHOT=1 also copies it to
// docs/view_screenshot.png for the README).
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>

#include "chromium.h"
#include "test_support.h"
#include "throng/protocol/contacts.h"
#include "throng/protocol/dds_transport.h"

namespace throng::view {
namespace {

using namespace testing;

const std::string kServer = THRONG_BIN_DIR "/throng-server";
const std::string kView = THRONG_BIN_DIR "/throng-view";
constexpr int kDomain = 203;

// Drags the canvas from (x, y) by (dx, dy) CSS pixels in 10 steps.
void drag(Cdp& cdp, double x, double y, double dx, double dy) {
  cdp.call("Input.dispatchMouseEvent", {{"type", "mousePressed"}, {"x", x}, {"y", y}, {"button", "left"}, {"buttons", 1}, {"clickCount", 1}});
  for (int i = 1; i <= 10; ++i)
    cdp.call("Input.dispatchMouseEvent",
             {{"type", "mouseMoved"}, {"x", x + dx * i / 10}, {"y", y + dy * i / 10}, {"button", "left"}, {"buttons", 1}});
  cdp.call("Input.dispatchMouseEvent",
           {{"type", "mouseReleased"}, {"x", x + dx}, {"y", y + dy}, {"button", "left"}, {"buttons", 0}, {"clickCount", 1}});
}

// What the server wrote on the viewer's contacts topic, read by a participant of the test's own.
struct ContactsSpy {
  std::mutex mutex;
  std::map<std::uint32_t, std::string> partitions;  // client id -> snapshot partition (join replies)
  std::map<std::uint64_t, protocol::ContactPairs> by_tick;
};


TEST(ViewE2E, PageDrawsTheMatchAndKeysMoveTheEntityOnTheServer) {
  ASSERT_TRUE(std::filesystem::exists(kChromium))
      << kChromium << " is missing: the end-to-end test needs Debian's chromium package "
      << "(bash deploy/install-deps.sh, or apt-get install -y chromium)";
  TempDir dir;
  ChildProcess server(kServer,
                      {"--no-log", "--scene", "battle", "--npcs", "300", "--domain", std::to_string(kDomain), "--admin-port", "0",
                       "--duration", "110", "--summary-json", (dir / "summary.json").string(), "--client-timeout",
                       "60", "--log-level", "warn"},
                      dir / "server.out", dir / "server.log");
  ChildProcess view(kView, {"--domain", std::to_string(kDomain), "--port", "0", "--name", "view-e2e", "--quiet"},
                    dir / "view.out", dir / "view.err");
  std::optional<std::uint16_t> port;
  ASSERT_TRUE(wait_until([&] { return (port = view_port(dir / "view.out")).has_value(); }, 20s))
      << "throng-view printed no URL\n" << read_file(dir / "view.err");
  ASSERT_TRUE(wait_until([&] { return read_file(dir / "view.err").find("joined as client") != std::string::npos; }, 30s))
      << read_file(dir / "view.err") << read_file(dir / "server.log");

  Chromium chrome = start_chromium(dir);
  ASSERT_NE(chrome.devtools_port, 0) << "Chromium wrote no DevToolsActivePort within 30 s\n"
                                     << read_file(dir / "chrome.err");
  const std::string target = page_target(chrome.devtools_port);
  ASSERT_FALSE(target.empty()) << "no page target in Chromium's /json/list";
  Cdp cdp("127.0.0.1", chrome.devtools_port, target);
  cdp.call("Page.enable");
  const std::string url = "http://127.0.0.1:" + std::to_string(*port) + "/";
  cdp.call("Page.navigate", {{"url", url}});

  // Wait until the page has the match and draws frames with characters in them.
  const std::string stats_js = "window.throngView ? window.throngView.stats() : null";
  nlohmann::json stats;
  const bool drawing = wait_until(
      [&] {
        stats = cdp.evaluate(stats_js);
        return stats.is_object() && stats["match"] == true && stats["frames"].get<int>() > 30 &&
               stats["drawn"].get<int>() > 0 && !stats["self"].is_null();
      },
      30s);
  ASSERT_TRUE(drawing) << "the page never drew: " << stats.dump() << "\n" << read_file(dir / "view.err");

  // Every character the page reports in view is drawn, and the canvas really shows them.
  stats = cdp.evaluate(stats_js);
  EXPECT_EQ(stats["drawn"], stats["objects"]) << stats.dump();
  EXPECT_GT(stats["drawn"].get<int>(), 10) << stats.dump();
  const int in_view = stats["in_view"].get<int>();
  const int drawn = stats["drawn"].get<int>();
  EXPECT_LE(drawn, in_view + in_view / 5 + 5) << "drawn far more than the server counts in view: " << stats.dump();
  EXPECT_GE(drawn, in_view / 2) << "drawn far fewer than the server counts in view: " << stats.dump();
  EXPECT_GT(cdp.evaluate("window.throngView.factionPixels()").get<int>(), 200) << "no faction-coloured pixels";
  EXPECT_FALSE(stats["latency_ms"].is_null()) << stats.dump();
  EXPECT_GT(stats["kbps"].get<double>(), 0.0) << stats.dump();

  // Hold D for 1.5 s: the entity (as the server reports it in the snapshots) moves in +x.
  const double x0 = stats["self"]["x"].get<double>();
  const double y0 = stats["self"]["y"].get<double>();
  const nlohmann::json key = {{"key", "d"}, {"code", "KeyD"}, {"windowsVirtualKeyCode", 68}, {"nativeVirtualKeyCode", 68}};
  auto down = key;
  down["type"] = "keyDown";
  down["text"] = "d";
  auto up = key;
  up["type"] = "keyUp";
  cdp.call("Input.dispatchKeyEvent", down);
  std::this_thread::sleep_for(1500ms);
  cdp.call("Input.dispatchKeyEvent", up);
  std::this_thread::sleep_for(700ms);
  stats = cdp.evaluate(stats_js);
  const double dx = stats["self"]["x"].get<double>() - x0;
  const double dy = stats["self"]["y"].get<double>() - y0;
  EXPECT_GT(dx, 1.0) << "the entity did not move right on the server: dx " << dx << " dy " << dy << "\n"
                     << stats.dump();
  EXPECT_EQ(stats["errors"], 0) << "the gateway rejected the page's input: " << stats.dump();
  std::printf("entity moved dx %.2f m, dy %.2f m while D was held for 1.5 s\n", dx, dy);

  // Collision shapes on (C), the mouse over the own character (the camera centre): its tooltip.
  press_key(cdp, "c", "KeyC", 67);
  const auto size = cdp.evaluate("[innerWidth, innerHeight]");
  const double cx = size[0].get<double>() / 2, cy = size[1].get<double>() / 2;
  cdp.call("Input.dispatchMouseEvent", {{"type", "mouseMoved"}, {"x", cx}, {"y", cy}});
  EXPECT_TRUE(wait_until([&] { return !(stats = cdp.evaluate(stats_js))["tooltip"].is_null(); }, 5s)) << stats.dump();
  EXPECT_EQ(stats["show_shapes"], true);
  const std::string tooltip = stats["tooltip"].is_string() ? stats["tooltip"].get<std::string>() : "";
  std::string you = "#";  // built in steps: GCC 12 warns (-Wrestrict) on "#" + to_string(...) + "..."
  you += std::to_string(stats["entity"].get<std::uint32_t>());
  you += " (you)";
  EXPECT_NE(tooltip.find(you), std::string::npos)
      << tooltip;
  EXPECT_NE(tooltip.find("radius"), std::string::npos) << tooltip;
  const double kbps_overlay_off = stats["kbps"].get<double>();

  // Contacts overlay. A test participant reads the same samples the server writes for the viewer.
  ContactsSpy spy;
  protocol::ClientTransport spy_transport(protocol::TransportOptions{kDomain, true, "view-e2e-spy", std::nullopt});
  protocol::ClientTransport::Handlers spy_handlers;
  spy_handlers.on_join_reply = [&spy](protocol::JoinReply&& r) {
    std::lock_guard lock(spy.mutex);
    spy.partitions[r.client_id] = r.snapshot_partition;
  };
  spy_transport.start(std::move(spy_handlers));
  const std::uint32_t client_id = stats["client_id"].get<std::uint32_t>();
  std::string partition;
  ASSERT_TRUE(wait_until(
      [&] {
        std::lock_guard lock(spy.mutex);
        const auto it = spy.partitions.find(client_id);
        if (it != spy.partitions.end()) partition = it->second;
        return !partition.empty();
      },
      15s))
      << "the test never saw the viewer's join reply";
  spy_transport.subscribe_contacts(client_id, partition, [&spy](protocol::ContactPairs&& c, std::size_t) {
    std::lock_guard lock(spy.mutex);
    spy.by_tick[c.tick] = std::move(c);
  });

  // Zoom in (the ratios are printed from 24 px/m on), then pan the camera to the battle's centre
  // line, where the armies meet: the server picks the pairs around the client's camera.
  cdp.call("Input.dispatchMouseEvent", {{"type", "mouseWheel"}, {"x", cx}, {"y", cy}, {"deltaX", 0}, {"deltaY", -900}});
  stats = cdp.evaluate(stats_js);
  const double zoom = stats["zoom"].get<double>();
  double to_go_px = stats["self"]["x"].get<double>() * zoom;  // drag right = camera left
  while (std::abs(to_go_px) > 1.0) {
    const double step = std::clamp(to_go_px, -cx * 0.8, cx * 0.8);
    drag(cdp, cx - step / 2, cy, step, 0.0);
    to_go_px -= step;
  }
  nlohmann::json pairs;
  const bool got_contacts = wait_until(
      [&] {
        // One evaluation for both: the page takes in new contacts between two of them, and the
        // pairs must be those of the tick the stats name.
        const nlohmann::json both = cdp.evaluate("[window.throngView.stats(), window.throngView.contacts()]");
        if (!both.is_array() || both.size() != 2) return false;
        stats = both[0];
        if (!stats["contacts"].is_object() || stats["contacts"]["pairs"].get<int>() < 3 || stats["contacts_drawn"].get<int>() < 3)
          return false;
        pairs = both[1];
        std::lock_guard lock(spy.mutex);
        return spy.by_tick.contains(stats["contacts"]["tick"].get<std::uint64_t>());
      },
      45s);
  ASSERT_TRUE(got_contacts) << "no contact pairs drawn: " << stats.dump() << "\n" << read_file(dir / "view.err");
  {
    std::lock_guard lock(spy.mutex);
    const protocol::ContactPairs& server_pairs = spy.by_tick.at(stats["contacts"]["tick"].get<std::uint64_t>());
    ASSERT_EQ(pairs.size(), server_pairs.a.size()) << pairs.dump();
    EXPECT_EQ(stats["contacts"]["near"], server_pairs.pairs_near);
    int drawn_pairs = 0;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      const double share = pairs[i]["share"].get<double>();
      EXPECT_EQ(pairs[i]["a"], server_pairs.a[i]);
      EXPECT_EQ(pairs[i]["b"], server_pairs.b[i]);
      EXPECT_NEAR(share, protocol::dequantize_share(server_pairs.share_a[i]), 1e-5) << "pair " << i;
      EXPECT_GT(share, 0.0);
      EXPECT_LT(share, 1.0);
      drawn_pairs += pairs[i]["drawn"] == true;
    }
    EXPECT_GE(drawn_pairs, 3) << pairs.dump();
    EXPECT_LE(server_pairs.a.size(), 32u) << "the server's per-client cap";
  }
  EXPECT_GT(cdp.evaluate("window.throngView.planePixels()").get<int>(), 20) << "no contact plane on the canvas";
  std::this_thread::sleep_for(1200ms);  // a full second of the overlay for the bandwidth figures
  stats = cdp.evaluate(stats_js);
  std::printf("snapshots %.1f kbit/s with the overlay off, %.1f kbit/s with it on; contacts channel %.1f kbit/s "
              "(%d pairs, %d near the camera)\n",
              kbps_overlay_off, stats["kbps"].get<double>(), stats["contacts_kbps"].get<double>(),
              stats["contacts"]["pairs"].get<int>(), stats["contacts"]["near"].get<int>());
  EXPECT_GT(stats["contacts_kbps"].get<double>(), 0.0);

  // The screenshot artifact.
  const std::string png = save_screenshot(cdp, "view_e2e.png", "view_screenshot.png");
  ASSERT_GT(png.size(), 1000u);
  EXPECT_EQ(png.substr(1, 3), "PNG");

  // C again: the overlay and the contacts request are off (frames carry no pairs any more).
  press_key(cdp, "c", "KeyC", 67);
  EXPECT_TRUE(wait_until([&] { return (stats = cdp.evaluate(stats_js))["contacts"].is_null(); }, 5s)) << stats.dump();
  EXPECT_EQ(stats["show_shapes"], false);

  // F follows the character again; a drag pans the camera, and the gateway then sends the server
  // the panned camera (interest area).
  press_key(cdp, "f", "KeyF", 70);
  EXPECT_TRUE(wait_until([&] { return (stats = cdp.evaluate(stats_js))["panned"] == false; }, 5s));
  drag(cdp, cx, cy, -200.0, 0.0);
  // Dragging 200 px left moves the camera 200 px / zoom to the right of the character; the frames
  // report the camera of the last command sent, so wait for the page's next inputs to get through.
  const bool panned = wait_until(
      [&] {
        stats = cdp.evaluate(stats_js);
        if (stats["panned"] != true || !stats["camera"].is_object() || stats["camera"]["panned"] != true) return false;
        const double expect_dx = 200.0 / stats["zoom"].get<double>();
        return std::abs(stats["camera"]["x"].get<double>() - stats["self"]["x"].get<double>() - expect_dx) < 1.0;
      },
      5s);
  EXPECT_TRUE(panned) << "the panned camera did not reach the server's commands: " << stats.dump();

  try {
    cdp.call("Browser.close", nlohmann::json::object(), 5s);
  } catch (const std::exception&) {
  }
  chrome.process->wait(5s);
  chrome.process->kill_now();

  // throng-view leaves on SIGTERM; the server's summary shows its commands were all accepted.
  view.signal(SIGTERM);
  const auto view_code = view.wait(15s);
  ASSERT_TRUE(view_code) << "throng-view did not exit after SIGTERM";
  EXPECT_EQ(*view_code, 0) << read_file(dir / "view.err");
  server.signal(SIGTERM);
  ASSERT_TRUE(server.wait(30s)) << "throng-server did not exit after SIGTERM";
  const auto summary = nlohmann::json::parse(read_file(dir / "summary.json"), nullptr, false);
  ASSERT_FALSE(summary.is_discarded()) << read_file(dir / "server.log");
  const nlohmann::json* me = nullptr;
  for (const auto& c : summary["clients"])
    if (c.value("name", "") == "view-e2e") me = &c;
  ASSERT_NE(me, nullptr) << summary.dump(2);
  EXPECT_GT((*me)["commands_accepted"].get<std::uint64_t>(), 30u) << me->dump();
  // Nothing the gateway sent was invalid (it is the only client). Two reasons are not the
  // gateway's doing. rate_limited: when this shared machine stalls the server's tick, more than
  // max-commands-per-tick of its commands wait for one tick (seen twice in ~10 runs, 5 rejections
  // each time). unknown_client, at most a command or two: the page's last command and the leave
  // travel on different topics, and when both land in the same tick the server applies the leave
  // first (joins and leaves before commands), so the last command finds no client (seen once in a
  // CI run, 1 rejection after "departure": "left").
  std::uint64_t invalid = 0, late_after_leave = 0;
  for (const auto& [reason, n] : summary["rejected_by_reason"].items()) {
    if (reason == "unknown_client") late_after_leave += n.get<std::uint64_t>();
    else if (reason != "rate_limited") invalid += n.get<std::uint64_t>();
  }
  EXPECT_EQ(invalid, 0u) << me->dump() << "\n" << summary["rejected_by_reason"].dump();
  EXPECT_LE(late_after_leave, 2u) << me->dump() << "\n" << summary["rejected_by_reason"].dump();
  EXPECT_EQ((*me)["departure"], "left") << me->dump();
}

// A match with DDS Security, viewed as a player: throng-view authenticates with the player's
// identity from a throng-pki directory, joins, gets the partition named after its certificate, and
// the page draws the match from its own snapshots.
TEST(ViewE2E, SecureMatchViewedAsAPlayer) {
  ASSERT_TRUE(std::filesystem::exists(kChromium)) << kChromium << " is missing (bash deploy/install-deps.sh)";
  constexpr int kSecureDomain = 216;
  TempDir dir;
  const std::string pki = (dir / "pki").string();
  const std::string make = std::string(THRONG_BIN_DIR) + "/throng-pki init " + pki + " >/dev/null 2>&1 && " +
                           THRONG_BIN_DIR + "/throng-pki client " + pki + " alice >/dev/null 2>&1";
  ASSERT_EQ(std::system(make.c_str()), 0);
  ChildProcess server(kServer,
                      {"--no-log", "--scene", "battle", "--npcs", "300", "--domain", std::to_string(kSecureDomain),
                       "--admin-port", "-1", "--duration", "60", "--security", pki, "--log-level", "info"},
                      dir / "server.out", dir / "server.log");
  ChildProcess view(kView,
                    {"--domain", std::to_string(kSecureDomain), "--port", "0", "--name", "alice-view", "--quiet",
                     "--security", pki, "--identity", "alice"},
                    dir / "view.out", dir / "view.err");
  std::optional<std::uint16_t> port;
  ASSERT_TRUE(wait_until([&] { return (port = view_port(dir / "view.out")).has_value(); }, 20s)) << read_file(dir / "view.err");
  ASSERT_TRUE(wait_until([&] { return read_file(dir / "view.err").find("joined as client") != std::string::npos; }, 30s))
      << read_file(dir / "view.err") << read_file(dir / "server.log");
  EXPECT_NE(read_file(dir / "server.log").find("partition throng_p_player-alice_1"), std::string::npos)
      << read_file(dir / "server.log");

  Chromium chrome = start_chromium(dir);
  ASSERT_NE(chrome.devtools_port, 0) << read_file(dir / "chrome.err");
  Cdp cdp("127.0.0.1", chrome.devtools_port, page_target(chrome.devtools_port));
  cdp.call("Page.enable");
  cdp.call("Page.navigate", {{"url", "http://127.0.0.1:" + std::to_string(*port) + "/"}});
  nlohmann::json stats;
  EXPECT_TRUE(wait_until(
      [&] {
        stats = cdp.evaluate("window.throngView ? window.throngView.stats() : null");
        return stats.is_object() && stats["match"] == true && stats["drawn"].get<int>() > 10 && !stats["self"].is_null();
      },
      30s))
      << "the page never drew the secure match: " << stats.dump() << "\n" << read_file(dir / "view.err");
}

}  // namespace
}  // namespace throng::view
