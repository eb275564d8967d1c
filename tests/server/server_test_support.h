#pragma once
// In-process server + DDS test client for the integration tests. Everything waits on condition
// variables with a deadline, so a broken server fails a test in seconds instead of hanging ctest.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "throng/protocol/codec.h"
#include "throng/protocol/dds_transport.h"
#include "throng/server/match_server.h"
#include "support/child_process.h"

namespace throng::test {

using namespace std::chrono_literals;

// Each test passes its own domain id (140..169, 194..199, 207..209 and 230..231 belong to tests/server) so parallel
// ctest runs never see each other's participants.
// One HTTP/1.1 GET to 127.0.0.1:port; the raw response ("" when nothing listens).
inline std::string http_get(std::uint16_t port, const std::string& path) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    ::close(fd);
    return {};
  }
  const std::string req = "GET " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
  (void)!::write(fd, req.data(), req.size());
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) > 0;) out.append(buf, static_cast<std::size_t>(n));
  ::close(fd);
  return out;
}

// The admin port a throng-server process started with --admin-port 0 reports on stderr (written
// to `err`), once it does; 0 if it has not within the timeout.
inline std::uint16_t wait_for_admin_port(const std::filesystem::path& err, std::chrono::milliseconds timeout = 30s) {
  const std::regex line("admin listening on 127\\.0\\.0\\.1:([0-9]+)");
  for (auto deadline = std::chrono::steady_clock::now() + timeout; std::chrono::steady_clock::now() < deadline;
       std::this_thread::sleep_for(50ms)) {
    std::smatch m;
    const std::string text = read_file(err);
    if (std::regex_search(text, m, line)) return static_cast<std::uint16_t>(std::stoi(m[1]));
  }
  return 0;
}

inline server::ServerOptions small_server_options(int domain) {
  server::ServerOptions o;
  o.scene = "battle";
  o.npcs = 400;
  o.domain = domain;
  o.admin_port = -1;
  o.log_level = "warn";
  o.log_file.clear();  // tests that want a match log set a path in a temp dir
  o.match.tick_hz = 30;
  o.match.client_timeout_s = 30.0;
  return o;
}

// A MatchServer running on its own thread until stop().
class ServerThread {
 public:
  explicit ServerThread(const server::ServerOptions& o)
      : server_(o), thread_([this] {
          exit_code_ = server_.run(false);
          done_.store(true);
        }) {}
  ~ServerThread() { stop(); }
  void stop() {
    if (thread_.joinable()) {
      server_.request_stop();
      thread_.join();
    }
  }
  server::MatchServer& server() { return server_; }
  int exit_code() const { return exit_code_; }
  // The match ended by itself (run() returned) without stop().
  bool done() const { return done_.load(); }

 private:
  server::MatchServer server_;
  int exit_code_ = -1;
  std::atomic<bool> done_{false};
  std::thread thread_;
};

// Commands are best-effort: one written before the server's command reader matched its writer is
// lost. A participant that has not had a command applied yet waits here until the server's reader
// counts `writers` command writers before its commands are counted on.
inline bool wait_for_command_writers(ServerThread& server, std::uint64_t writers, std::chrono::milliseconds timeout = 10s) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (server.server().transport_counters().command_writers < writers) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(10ms);
  }
  return true;
}

// A TCP port nobody listens on at the moment of asking (the test then listens on it). Taken below
// the kernel's ephemeral range (32768 and up), where no outgoing connection of another process or
// test can be handed the port in the moment between this probe and the server's listen.
inline std::uint16_t free_tcp_port() {
  const std::uint16_t first = static_cast<std::uint16_t>(20000 + (::getpid() * 53) % 12000);
  for (std::uint32_t k = 0; k < 12000; ++k) {
    const std::uint16_t port = static_cast<std::uint16_t>(20000 + (first - 20000 + k) % 12000);
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_ANY);
    a.sin_port = htons(port);
    const bool free = ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
    ::close(fd);
    if (free) return port;
  }
  return 0;
}

// A client participant that reaches the server only over TCP, at 127.0.0.1:port.
inline protocol::TransportOptions tcp_client_options(int domain, std::uint16_t port, const std::string& name) {
  protocol::TransportOptions t{domain, true, name, std::nullopt};
  t.server_endpoint = protocol::NetEndpoint{"127.0.0.1", port};
  return t;
}

// One client on its own participant; records everything it receives.
class TestClient {
 public:
  explicit TestClient(int domain) : TestClient(protocol::TransportOptions{domain, true, "throng-test-client", std::nullopt}) {}
  // Any transport options (DDS Security: discovery and the handshakes take longer, so patience).
  explicit TestClient(const protocol::TransportOptions& options, std::chrono::milliseconds patience = 10s)
      : patience_(patience), transport_(options) {
    transport_.start(protocol::ClientTransport::Handlers{
        [this](protocol::MatchInfo&& m) { locked([&] { match_infos_.push_back(std::move(m)); }); },
        [this](protocol::JoinReply&& r) { locked([&] { replies_.push_back(std::move(r)); }); },
        [this](protocol::ParamReply&& r) { locked([&] { param_replies_.push_back(std::move(r)); }); },
        [this](protocol::ServerStats&& s) { locked([&] { stats_.push_back(std::move(s)); }); },
    });
  }

  protocol::ClientTransport& transport() { return transport_; }

  // Joins and subscribes to the snapshot partition; returns the reply (nullopt on timeout).
  std::optional<protocol::JoinReply> join(std::uint64_t nonce, const std::string& name = "test",
                                          std::uint32_t version = protocol::kProtocolVersion) {
    if (!transport_.wait_for_server(patience_)) return std::nullopt;
    protocol::JoinRequest r;
    r.client_nonce = nonce;
    r.name = name;
    r.protocol_version = version;
    transport_.send_join(r);
    std::optional<protocol::JoinReply> reply;
    wait_until(
        [&] {
          for (const auto& x : replies_)
            if (x.client_nonce == nonce) reply = x;
          return reply.has_value();
        },
        patience_);
    if (reply && reply->result == protocol::JoinResult::accepted) subscribe(reply->client_id, reply->snapshot_partition);
    return reply;
  }

  // Leaves as the client that joined with `nonce`; true once the server answered "left".
  bool leave(std::uint64_t nonce, std::uint32_t client_id) {
    protocol::JoinRequest r;
    r.client_nonce = nonce;
    r.leave = true;
    r.client_id = client_id;
    transport_.send_join(r);
    return wait_until([&] {
      for (const auto& x : replies_)
        if (x.client_nonce == nonce && x.result == protocol::JoinResult::left) return true;
      return false;
    });
  }

  // Records client_id's snapshots from `partition` (subscribing again re-points the reader).
  void subscribe(std::uint32_t client_id, const std::string& partition) {
    transport_.subscribe_snapshots(client_id, partition,
                                   [this](protocol::Snapshot&& s, std::size_t) { locked([&] { snapshots_.push_back(std::move(s)); }); });
  }

  // Waits (bounded) until pred() holds; pred runs under the lock.
  bool wait_until(const std::function<bool()>& pred, std::chrono::milliseconds timeout = 10s) {
    std::unique_lock lock(mutex_);
    return cv_.wait_for(lock, timeout, pred);
  }

  template <typename F>
  auto with_lock(F&& f) {
    std::lock_guard lock(mutex_);
    return f();
  }

  std::vector<protocol::MatchInfo>& match_infos() { return match_infos_; }
  std::deque<protocol::Snapshot>& snapshots() { return snapshots_; }
  std::vector<protocol::JoinReply>& replies() { return replies_; }
  std::vector<protocol::ParamReply>& param_replies() { return param_replies_; }
  std::vector<protocol::ServerStats>& stats() { return stats_; }

 private:
  template <typename F>
  void locked(F&& f) {
    {
      std::lock_guard lock(mutex_);
      f();
    }
    cv_.notify_all();
  }

  std::chrono::milliseconds patience_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<protocol::MatchInfo> match_infos_;
  std::vector<protocol::JoinReply> replies_;
  std::vector<protocol::ParamReply> param_replies_;
  std::vector<protocol::ServerStats> stats_;
  std::deque<protocol::Snapshot> snapshots_;
  protocol::ClientTransport transport_;  // last: destroyed first, so no callback outlives the rest
};

// A command that stands still and keeps the camera fixed: applying it changes nothing in the world.
inline protocol::Command standing_command(const protocol::JoinReply& r, std::uint32_t seq) {
  protocol::Command c;
  c.client_id = r.client_id;
  c.entity = r.entity;
  c.sequence = seq;
  c.camera_z = 10.0f;
  return c;
}

// A client that joins over TCP (tcp_client_options). Its discovery sometimes never completes (Fast
// DDS 2.9 over TCP on one host, in about one ctest run in five; reproduced before the hot standby
// existed, cause not found): then a fresh client participant tries once more.
struct TcpJoin {
  std::unique_ptr<TestClient> client;
  std::optional<protocol::JoinReply> reply;
  bool accepted() const { return reply && reply->result == protocol::JoinResult::accepted; }
};
inline TcpJoin join_over_tcp(int domain, std::uint16_t port, const std::string& name, std::uint64_t nonce) {
  TcpJoin j;
  for (int attempt = 0; attempt < 2 && !j.accepted(); ++attempt) {
    j.client.reset();
    j.client = std::make_unique<TestClient>(tcp_client_options(domain, port, name), 12s);
    j.reply = j.client->join(nonce, name);
  }
  return j;
}

// Snapshots of one client in a recorded list, and the newest command sequence they say was applied.
inline std::size_t snapshots_of(const std::deque<protocol::Snapshot>& snapshots, std::uint32_t client_id) {
  std::size_t n = 0;
  for (const auto& s : snapshots) n += s.client_id == client_id;
  return n;
}
inline std::uint32_t last_applied(const std::deque<protocol::Snapshot>& snapshots, std::uint32_t client_id) {
  std::uint32_t seq = 0;
  for (const auto& s : snapshots)
    if (s.client_id == client_id) seq = s.last_applied_sequence;
  return seq;
}

// What a hijacker does from its own participant with what every join reply tells: `commands`
// full-speed commands for the victim's client and entity with sequences from first_sequence on
// (far ahead of the victim's), then a leave naming the victim's client and nonce.
inline void hijack_and_kick(protocol::ClientTransport& attacker, const protocol::JoinReply& victim, std::uint32_t commands,
                            std::uint32_t first_sequence) {
  for (std::uint32_t k = 0; k < commands; ++k) {
    protocol::Command c = standing_command(victim, first_sequence + k);
    c.move_x = 1.0f;
    attacker.send_command(c);
    std::this_thread::sleep_for(5ms);
  }
  protocol::JoinRequest kick;
  kick.client_nonce = victim.client_nonce;
  kick.leave = true;
  kick.client_id = victim.client_id;
  attacker.send_join(kick);
  std::this_thread::sleep_for(300ms);
}

// Own pose as the snapshots report it.
struct OwnPose {
  std::uint64_t tick = 0;
  double x = 0, y = 0;
};

}  // namespace throng::test
