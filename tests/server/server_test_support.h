#pragma once
// In-process server + DDS test client for the integration tests. Everything waits on condition
// variables with a deadline, so a broken server fails a test in seconds instead of hanging ctest.
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "throng/protocol/codec.h"
#include "throng/protocol/dds_transport.h"
#include "throng/server/match_server.h"

namespace throng::test {

using namespace std::chrono_literals;

// Each test passes its own domain id (140..169 belong to tests/server) so parallel ctest runs
// never see each other's participants.
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
  explicit ServerThread(const server::ServerOptions& o) : server_(o), thread_([this] { exit_code_ = server_.run(false); }) {}
  ~ServerThread() { stop(); }
  void stop() {
    if (thread_.joinable()) {
      server_.request_stop();
      thread_.join();
    }
  }
  server::MatchServer& server() { return server_; }
  int exit_code() const { return exit_code_; }

 private:
  server::MatchServer server_;
  int exit_code_ = -1;
  std::thread thread_;
};

// One client on its own participant; records everything it receives.
class TestClient {
 public:
  explicit TestClient(int domain) : transport_(protocol::TransportOptions{domain, true, "throng-test-client", std::nullopt}) {
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
    if (!transport_.wait_for_server(10s)) return std::nullopt;
    protocol::JoinRequest r;
    r.client_nonce = nonce;
    r.name = name;
    r.protocol_version = version;
    transport_.send_join(r);
    std::optional<protocol::JoinReply> reply;
    wait_until([&] {
      for (const auto& x : replies_)
        if (x.client_nonce == nonce) reply = x;
      return reply.has_value();
    });
    if (reply && reply->result == protocol::JoinResult::accepted) {
      transport_.subscribe_snapshots(reply->client_id, reply->snapshot_partition,
                                     [this](protocol::Snapshot&& s, std::size_t) { locked([&] { snapshots_.push_back(std::move(s)); }); });
    }
    return reply;
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

  std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<protocol::MatchInfo> match_infos_;
  std::vector<protocol::JoinReply> replies_;
  std::vector<protocol::ParamReply> param_replies_;
  std::vector<protocol::ServerStats> stats_;
  std::deque<protocol::Snapshot> snapshots_;
  protocol::ClientTransport transport_;  // last: destroyed first, so no callback outlives the rest
};

// Own pose as the snapshots report it.
struct OwnPose {
  std::uint64_t tick = 0;
  double x = 0, y = 0;
};

}  // namespace throng::test
