// The Agones lifecycle (server/app/include/throng/server/agones_sdk.h) against an SDK double: a small
// HTTP server in the test standing in for the Agones sidecar, recording every request. Also the
// end of a match by itself once every player has left (--end-when-empty).
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "server_test_support.h"

namespace throng::test {
namespace {

using Clock = std::chrono::steady_clock;

// The sidecar's REST gateway as far as the server uses it: answers 200 "{}" to everything and
// records method, path, body and arrival time.
class SdkDouble {
 public:
  struct Request {
    std::string method, path, body;
    Clock::time_point at;
  };

  // port 0: any free port.
  explicit SdkDouble(std::uint16_t port = 0) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    const int one = 1;
    ::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || ::listen(fd_, 16) != 0) {
      ADD_FAILURE() << "SDK double cannot listen on port " << port;
      return;
    }
    socklen_t len = sizeof a;
    ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    thread_ = std::thread([this] { serve(); });
  }
  ~SdkDouble() {
    stopping_ = true;
    ::shutdown(fd_, SHUT_RDWR);
    ::close(fd_);
    if (thread_.joinable()) thread_.join();
  }
  std::uint16_t port() const { return port_; }
  // The body of GET /gameserver (Agones's GameServer as JSON).
  void set_gameserver(std::string json) {
    std::lock_guard<std::mutex> lock(mutex_);
    gameserver_ = std::move(json);
  }
  std::vector<Request> requests() {
    std::lock_guard<std::mutex> lock(mutex_);
    return requests_;
  }
  std::vector<Request> of(const std::string& method, const std::string& path) {
    std::vector<Request> out;
    for (const auto& r : requests())
      if (r.method == method && r.path == path) out.push_back(r);
    return out;
  }
  bool wait_for(const std::string& method, const std::string& path, std::size_t count, std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    while (of(method, path).size() < count) {
      if (Clock::now() > deadline) return false;
      std::this_thread::sleep_for(10ms);
    }
    return true;
  }

 private:
  void serve() {
    while (!stopping_) {
      const int c = ::accept(fd_, nullptr, nullptr);
      if (c < 0) return;
      std::string in;
      char buf[2048];
      std::size_t need = std::string::npos;
      while (true) {
        const ssize_t n = ::recv(c, buf, sizeof buf, 0);
        if (n <= 0) break;
        in.append(buf, static_cast<std::size_t>(n));
        const auto head_end = in.find("\r\n\r\n");
        if (head_end == std::string::npos) continue;
        if (need == std::string::npos) {
          std::size_t length = 0;
          const auto cl = in.find("Content-Length: ");
          if (cl != std::string::npos && cl < head_end) length = std::stoul(in.substr(cl + 16));
          need = head_end + 4 + length;
        }
        if (in.size() >= need) break;
      }
      Request r;
      r.at = Clock::now();
      const auto sp1 = in.find(' '), sp2 = in.find(' ', sp1 + 1);
      if (sp1 != std::string::npos && sp2 != std::string::npos) {
        r.method = in.substr(0, sp1);
        r.path = in.substr(sp1 + 1, sp2 - sp1 - 1);
        const auto head_end = in.find("\r\n\r\n");
        if (head_end != std::string::npos) r.body = in.substr(head_end + 4);
      }
      std::string body = "{}";
      if (r.method == "GET" && r.path == "/gameserver") {
        std::lock_guard<std::mutex> lock(mutex_);
        body = gameserver_;
      }
      const std::string reply = "HTTP/1.1 200 OK\r\nContent-Type: application/json\r\nContent-Length: " +
                                std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body;
      (void)::send(c, reply.data(), reply.size(), MSG_NOSIGNAL);
      ::close(c);
      std::lock_guard<std::mutex> lock(mutex_);
      requests_.push_back(std::move(r));
    }
  }

  int fd_ = -1;
  std::uint16_t port_ = 0;
  std::atomic<bool> stopping_{false};
  std::mutex mutex_;
  std::vector<Request> requests_;
  std::string gameserver_ = "{}";
  std::thread thread_;
};

server::ServerOptions agones_options(int domain, std::uint16_t sdk_port) {
  auto o = small_server_options(domain);
  o.agones_port = sdk_port;
  o.agones_health_interval_ms = 200;
  return o;
}

// Ready, health pings, the player count as a label, and shutdown when the match ends by itself
// after its only player left.
TEST(Agones, ReadyHealthPlayersLabelAndShutdownWhenTheLastPlayerLeft) {
  SdkDouble sdk;
  auto o = agones_options(161, sdk.port());
  o.end_when_empty_s = 0.5;
  ServerThread server(o);
  ASSERT_TRUE(sdk.wait_for("POST", "/ready", 1, 10s));
  ASSERT_TRUE(sdk.wait_for("POST", "/health", 3, 10s));
  {
    TestClient client(161);
    const auto r = client.join(31, "player");
    ASSERT_TRUE(r && r->result == protocol::JoinResult::accepted);
    const auto label_is = [&](const char* n) {
      for (const auto& q : sdk.of("PUT", "/metadata/label"))
        if (q.body == std::string("{\"key\":\"players\",\"value\":\"") + n + "\"}") return true;
      return false;
    };
    ASSERT_TRUE(client.wait_until([&] { return label_is("1"); })) << "no players=1 label";
    ASSERT_TRUE(client.leave(r->client_nonce, r->client_id)) << "no reply to the leave";
    ASSERT_TRUE(client.wait_until([&] { return label_is("0") && sdk.of("PUT", "/metadata/label").size() >= 3; }));
  }
  // Nobody joins again: the match ends by itself and tells Agones.
  const auto deadline = Clock::now() + 10s;
  while (!server.done() && Clock::now() < deadline) std::this_thread::sleep_for(20ms);
  ASSERT_TRUE(server.done()) << "the match did not end after its last player left";
  EXPECT_EQ(server.exit_code(), 0);
  EXPECT_EQ(server.server().summary()["end_reason"], "empty");
  const auto all = sdk.requests();
  ASSERT_FALSE(all.empty());
  EXPECT_EQ(all.front().path, "/ready");
  EXPECT_EQ(all.back().method + " " + all.back().path, "POST /shutdown");
  EXPECT_EQ(sdk.of("POST", "/shutdown").size(), 1u);
  // Pings about every 200 ms (the double answers at once; allow for a loaded machine).
  const auto pings = sdk.of("POST", "/health");
  for (std::size_t k = 1; k < pings.size(); ++k) EXPECT_GE(pings[k].at - pings[k - 1].at, 150ms) << "ping " << k;
}

// A tick that takes 1.5 s withholds the pings meanwhile (Agones marks the server Unhealthy after
// its failure threshold); they resume with the ticks.
TEST(Agones, AStuckTickWithholdsHealthPings) {
  SdkDouble sdk;
  auto o = agones_options(162, sdk.port());
  std::atomic<bool> stalled{false};
  o.tick_hook_for_tests = [&](std::uint64_t tick) {
    if (tick == 40) {
      stalled = true;
      std::this_thread::sleep_for(1500ms);
    }
  };
  ServerThread server(o);
  ASSERT_TRUE(sdk.wait_for("POST", "/ready", 1, 10s));
  const auto deadline = Clock::now() + 15s;
  while (!stalled && Clock::now() < deadline) std::this_thread::sleep_for(10ms);
  ASSERT_TRUE(stalled.load());
  const std::size_t before = sdk.of("POST", "/health").size();
  ASSERT_TRUE(sdk.wait_for("POST", "/health", before + 3, 10s)) << "pings did not resume after the stall";
  server.stop();
  const auto pings = sdk.of("POST", "/health");
  Clock::duration longest{};
  for (std::size_t k = 1; k < pings.size(); ++k) longest = std::max(longest, pings[k].at - pings[k - 1].at);
  EXPECT_GE(longest, 1200ms) << "pings went on while the tick was stuck";
  EXPECT_EQ(sdk.of("POST", "/shutdown").size(), 1u);
}

// The sidecar may start after the game server: the server keeps trying until it answers.
TEST(Agones, ASidecarThatStartsLateStillHearsReadyAndShutdown) {
  std::uint16_t port = 0;
  { SdkDouble probe; port = probe.port(); }  // a port that was free a moment ago
  ServerThread server(agones_options(163, port));
  std::this_thread::sleep_for(1000ms);
  SdkDouble sdk(port);
  ASSERT_TRUE(sdk.wait_for("POST", "/ready", 1, 10s));
  ASSERT_TRUE(sdk.wait_for("POST", "/health", 2, 10s));
  server.stop();
  EXPECT_EQ(server.server().summary()["end_reason"], "stopped");
  EXPECT_EQ(sdk.of("POST", "/shutdown").size(), 1u);
  EXPECT_EQ(sdk.requests().front().path, "/ready");
}

// --listen agones: the server listens on the port Agones allocated to "dds" (portPolicy
// Passthrough) and players connect to it.
TEST(Agones, ListensOnThePortAgonesAllocatedToDds) {
  SdkDouble sdk;
  const std::uint16_t port = free_tcp_port();
  sdk.set_gameserver(R"({"object_meta":{"name":"throng-abc"},"status":{"state":"Scheduled","address":"127.0.0.1",)"
                     R"("ports":[{"name":"admin","port":1},{"name":"dds","port":)" + std::to_string(port) + "}]}}");
  auto o = agones_options(166, sdk.port());
  o.listen = server::kListenAgones;
  ServerThread server(o);
  const TcpJoin player = join_over_tcp(166, port, "agones-player", 5);
  ASSERT_TRUE(player.accepted());
  ASSERT_FALSE(sdk.of("GET", "/gameserver").empty());
  server.stop();
}


// --end-when-routed: a side whose every group retreats (here: group 2's morale broken in the
// scene's table) has lost; the match ends by itself once that lasted the configured time.
TEST(MatchEnd, ARoutedSideEndsTheMatch) {
  const auto dir = std::filesystem::temp_directory_path() / ("throng-routed-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto scene = dir / "routed.json";
  {
    std::ofstream f(scene);
    f << R"({"version": 1, "name": "routed", "ticks": 100, "seed": 3,
      "params": {"archetypes": {"infantry": {"kind": "foot", "weight": 80}},
                 "groups": [{"id": 1}, {"id": 2, "morale": -50}]},
      "spawns": [
        {"name": "red", "count": 40, "shape": {"type": "rect", "centre": [-12, 0], "half_extents_m": [4, 4]},
         "radius_m": 0.35, "archetype": "infantry", "faction": 1, "group": 1,
         "behaviour": {"type": "march", "direction": [1, 0], "speed_mps": 1.2}},
        {"name": "blue", "count": 40, "shape": {"type": "rect", "centre": [12, 0], "half_extents_m": [4, 4]},
         "radius_m": 0.35, "archetype": "infantry", "faction": 2, "group": 2,
         "behaviour": {"type": "march", "direction": [-1, 0], "speed_mps": 1.2}}]})";
  }
  auto o = small_server_options(167);
  o.scene = scene.string();
  o.npcs = 0;
  o.end_when_routed_s = 0.3;
  ServerThread server(o);
  const auto deadline = Clock::now() + 10s;
  while (!server.done() && Clock::now() < deadline) std::this_thread::sleep_for(20ms);
  ASSERT_TRUE(server.done()) << "the match did not end although side 2 was routed";
  EXPECT_EQ(server.exit_code(), 0);
  EXPECT_EQ(server.server().summary()["end_reason"], "routed");

  // The same match without the option runs until stopped.
  o.end_when_routed_s = 0.0;
  o.domain = 168;
  ServerThread steady(o);
  std::this_thread::sleep_for(1s);
  EXPECT_FALSE(steady.done());
  steady.stop();
  EXPECT_EQ(steady.server().summary()["end_reason"], "stopped");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace throng::test
