#pragma once
// One simulated client, transport-free: the Fleet moves its messages. A bot joins with a random
// nonce, learns its client id/entity/partition from the JoinReply, keeps a ClientWorld from its
// snapshots, and once it has seen its own entity emits its behavior's commands once per loop
// tick (camera = its entity). Thread-safe: snapshots arrive on DDS threads while the fleet's loop
// ticks the bot; every public member locks the bot's mutex.
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "throng/client_sim/behavior.h"
#include "throng/client_sim/bot_metrics.h"
#include "throng/client_sim/client_world.h"
#include "throng/client_sim/join_handshake.h"
#include "throng/client_sim/report.h"
#include "throng/protocol/messages.h"

namespace throng::client_sim {

struct BotConfig {
  std::string name;              // at most 64 bytes (the server refuses longer)
  std::string behavior = "wander";
  std::uint64_t nonce = 0;       // non-zero; 0 draws one from std::random_device
  std::uint64_t seed = 0;        // behavior randomness; 0 draws one from std::random_device
  ClientWorld::Options world{};
};

class Bot {
 public:
  using State = JoinHandshake::State;
  static const char* to_string(State s) { return JoinHandshake::to_string(s); }

  // Throws std::invalid_argument for an unknown behavior.
  Bot(BotConfig config, TimePoint launch);

  const std::string& name() const { return config_.name; }
  const std::string& behavior() const { return config_.behavior; }
  std::uint64_t nonce() const { return config_.nonce; }
  State state() const;
  std::uint32_t client_id() const;
  std::uint32_t entity() const;
  std::string partition() const;
  std::optional<TimePoint> join_sent_at() const;       // first join request
  std::optional<TimePoint> last_join_sent_at() const;  // latest (re)sent join request
  bool has_first_snapshot() const;

  // Marks the bot joining and returns the request to send. Called again while joining it returns
  // the same request for a resend (the server answers a repeated nonce with its original reply).
  protocol::JoinRequest join_request(TimePoint now);
  // The reply for this bot's nonce. Returns true when it was accepted now (the owner subscribes
  // the bot's snapshots then); a repeated or late reply returns false.
  bool on_join_reply(const protocol::JoinReply& reply);
  bool on_join_reply(const protocol::JoinReply& reply, TimePoint now);  // now: when it arrived
  void mark_timed_out();  // created or joining -> timed_out
  // A joined bot that has received no snapshot for `silence` (its server is gone and nobody took
  // its match over) starts again as a new client: a new nonce, joining, its world, sequences and
  // pending commands reset. Returns the old client id (to unsubscribe its snapshots); nullopt
  // when not joined or not silent that long.
  std::optional<std::uint32_t> begin_rejoin(TimePoint now, std::chrono::milliseconds silence);
  std::uint32_t rejoins() const;
  // nullopt unless joined; marks the bot left.
  std::optional<protocol::JoinRequest> leave_request();

  void set_match(std::shared_ptr<const MatchView> match);
  void on_snapshot(const protocol::Snapshot& snapshot, std::size_t wire_bytes, TimePoint now);
  // Appends this tick's commands to out (none before the bot has seen its own entity).
  void tick(TimePoint now, std::span<const std::uint32_t> other_client_entities, std::vector<protocol::Command>& out);

  BotReport report(TimePoint now) const;
  Samples take_window_latency();
  std::optional<ObjectState> own_pose() const;
  std::optional<ObjectState> object(std::uint32_t id) const;  // at the render time
  std::size_t world_objects() const;
  std::uint64_t snapshots_received() const;
  std::uint64_t bytes_received() const;
  std::uint64_t missed_ticks() const;
  std::uint64_t commands_sent() const;

 private:
  class Sink;

  mutable std::mutex mutex_;
  BotConfig config_;
  std::unique_ptr<Behavior> behavior_;
  std::mt19937_64 rng_;
  JoinHandshake join_;  // after config_: made from its nonce and name
  std::uint32_t next_sequence_ = 1;
  std::uint32_t last_applied_sequence_ = 0;
  ClientWorld world_;
  BotMetrics metrics_;
  std::optional<ObjectState> first_pose_;
  std::optional<TimePoint> first_tick_time_;
  std::shared_ptr<const MatchView> match_;  // the newest, for a fresh world after a rejoin
  std::uint32_t rejoins_ = 0;
  std::optional<TimePoint> joined_at_;  // when the current client was accepted (steady clock)
};

}  // namespace throng::client_sim
