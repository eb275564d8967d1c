#pragma once
// Shared by the throng-replay play tests: a recorded log (the matchlog tests' small match: ~300
// bodies, six clients joining at ticks 2..7, operator changes at 40 and 90, client 5 leaving at
// 120, shutdown at the last tick), the player as a child process, and a DDS watcher that records
// everything it receives. Domains 210..229 belong to tests/play (one per test).
#include <chrono>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "matchlog/matchlog_test_util.h"
#include "support/child_process.h"
#include "throng/protocol/dds_transport.h"

namespace throng::play_test {

using namespace std::chrono_literals;

inline const std::string kReplay = std::string(THRONG_BIN_DIR) + "/throng-replay";
inline const std::string kBots = std::string(THRONG_BIN_DIR) + "/throng-bots";

// Records the small match (`ticks` long) to path, as throng-server would have; tamper_tick > 0
// writes that tick's hash wrong (a log this build "does not reproduce").
inline void record_log(const std::filesystem::path& path, std::uint64_t ticks, std::uint64_t tamper_tick = 0) {
  const auto played = matchlog::test::play_match(ticks);
  matchlog::test::write_played(path, played.ticks, matchlog::test::match_header(), {}, tamper_tick);
}

// A player process: `throng-replay play LOG --domain D -q args...`, output into dir.
inline std::unique_ptr<test::ChildProcess> start_player(const std::filesystem::path& log, int domain,
                                                        const std::vector<std::string>& args, const test::TempDir& dir) {
  std::vector<std::string> a = {"play", log.string(), "--domain", std::to_string(domain), "-q"};
  a.insert(a.end(), args.begin(), args.end());
  return std::make_unique<test::ChildProcess>(kReplay, a, dir / "play.out", dir / "play.err");
}

// A client on its own loopback participant; records what it receives, waits are bounded.
class Watcher {
 public:
  explicit Watcher(int domain) : transport_(protocol::TransportOptions{domain, true, "throng-play-test", std::nullopt}) {
    transport_.start(protocol::ClientTransport::Handlers{
        [this](protocol::MatchInfo&& m) { locked([&] { infos_.push_back(std::move(m)); }); },
        [this](protocol::JoinReply&& r) { locked([&] { replies_.push_back(std::move(r)); }); },
        [this](protocol::ParamReply&& r) { locked([&] { param_replies_.push_back(std::move(r)); }); },
        [this](protocol::ServerStats&& s) { locked([&] { stats_.push_back(std::move(s)); }); },
    });
  }

  protocol::ClientTransport& transport() { return transport_; }

  // Sends a join and waits for the reply with this nonce; subscribes to the snapshots if accepted.
  std::optional<protocol::JoinReply> join(std::uint64_t nonce, const std::string& name) {
    if (!transport_.wait_for_server(20s)) return std::nullopt;
    protocol::JoinRequest r;
    r.client_nonce = nonce;
    r.name = name;
    transport_.send_join(r);
    std::optional<protocol::JoinReply> reply;
    wait_until([&] {
      for (const auto& x : replies_)
        if (x.client_nonce == nonce) reply = x;
      return reply.has_value();
    });
    if (reply && reply->result == protocol::JoinResult::accepted) subscribe(reply->client_id, reply->snapshot_partition, own_);
    return reply;
  }

  // Listens to another client's partition too (the logged clients' streams).
  void listen(std::uint32_t client_id, const std::string& partition) { subscribe(client_id, partition, logged_); }

  bool wait_until(const std::function<bool()>& pred, std::chrono::milliseconds timeout = 20s) {
    std::unique_lock lock(mutex_);
    return cv_.wait_for(lock, timeout, pred);
  }
  template <typename F>
  auto with_lock(F&& f) {
    std::lock_guard lock(mutex_);
    return f();
  }

  // Read under with_lock / wait_until.
  std::vector<protocol::MatchInfo>& infos() { return infos_; }
  std::vector<protocol::JoinReply>& replies() { return replies_; }
  std::vector<protocol::ParamReply>& param_replies() { return param_replies_; }
  std::vector<protocol::ServerStats>& stats() { return stats_; }
  std::deque<protocol::Snapshot>& own_snapshots() { return own_; }
  std::deque<protocol::Snapshot>& logged_snapshots() { return logged_; }

 private:
  void subscribe(std::uint32_t id, const std::string& partition, std::deque<protocol::Snapshot>& into) {
    transport_.subscribe_snapshots(id, partition, [this, &into](protocol::Snapshot&& s, std::size_t) {
      locked([&] { into.push_back(std::move(s)); });
    });
  }
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
  std::vector<protocol::MatchInfo> infos_;
  std::vector<protocol::JoinReply> replies_;
  std::vector<protocol::ParamReply> param_replies_;
  std::vector<protocol::ServerStats> stats_;
  std::deque<protocol::Snapshot> own_, logged_;
  protocol::ClientTransport transport_;  // last: destroyed first, so no callback outlives the rest
};

}  // namespace throng::play_test
