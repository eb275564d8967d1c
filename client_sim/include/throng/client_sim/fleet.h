#pragma once
// Many bots over the real client path: ClientTransport participants (one shared by all bots, or
// one per bot), join routing by nonce, snapshot subscriptions, and one shared loop that sends
// every joined bot's commands once per server tick — no thread per bot.
//
// Send phases: the loop steps `phases_per_tick` times per tick and bot i sends in step i mod
// phases_per_tick, so the bots' sends are spread over the tick period like those of real,
// unsynchronized clients. With a single phase every bot would send at the same offset from the
// server's tick, and the measured latency would depend on the luck of that one offset.
//
// Threading: DDS listener threads only queue join replies, store MatchInfo/ServerStats and feed
// snapshots to their bot (which locks itself). Everything else — launch(), step(), leave_all()
// and the readers — is for one driving thread.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "throng/client_sim/bot.h"
#include "throng/client_sim/client_world.h"
#include "throng/client_sim/match_view.h"
#include "throng/client_sim/report.h"
#include "throng/protocol/dds_transport.h"
#include "throng/protocol/messages.h"

namespace throng::client_sim {

struct FleetOptions {
  int domain_id = 0;
  bool loopback_only = true;
  std::optional<protocol::NetEndpoint> server_endpoint;  // --server udp:// or tcp://HOST:PORT: DDS to that one server
  bool participant_per_client = false;
  std::optional<protocol::SecurityFiles> security;  // DDS Security (throng-pki's bots identity); nullopt: off
  std::string behavior = "wander";  // a behavior spec (expand_behavior_spec)
  std::string name_prefix = "bot";  // bot i is "<prefix>-<i>-<behavior>"
  std::uint64_t seed = 0;           // 0: nonces and behavior seeds from std::random_device
  std::chrono::milliseconds server_wait{10000};
  std::chrono::milliseconds join_timeout{10000};
  std::uint32_t phases_per_tick = 8;  // >= 1
  // Joins are paced: at most this many bots wait for a reply at once (the join-request writer
  // keeps a bounded history; a burst of hundreds would overwrite unacknowledged requests), and a
  // request without a reply is re-sent every join_resend (the server answers a repeated nonce
  // with its original reply).
  std::uint32_t max_pending_joins = 32;
  std::chrono::milliseconds join_resend{2000};
  // A joined bot that has received no snapshot for this long joins again as a new client (its
  // server died and nobody took the match over); 0 = never. A hot standby's takeover must leave
  // this at 0 rejoins (docs/design/standby.md).
  std::chrono::milliseconds rejoin_after{0};
  ClientWorld::Options world{};
};

struct FleetProgress {
  std::size_t launched = 0, joining = 0, joined = 0, active = 0, failed = 0;  // active: has snapshots
  std::uint64_t snapshots = 0, bytes = 0, missed_ticks = 0, commands_sent = 0;
};

class Fleet {
 public:
  // Throws std::invalid_argument for a bad behavior spec.
  explicit Fleet(FleetOptions options);
  ~Fleet();
  Fleet(const Fleet&) = delete;
  Fleet& operator=(const Fleet&) = delete;

  // Creates the shared participant (unless participant_per_client) and waits until the server's
  // readers are matched. Returns false when no server answered within server_wait. Throws
  // protocol::TransportError when the participant cannot be created.
  bool connect();

  // Launches n more bots and sends their joins (paced, see max_pending_joins: the rest go out
  // from step() as replies arrive). With participant_per_client each bot first gets its own
  // participant and waits for the server (a bot whose wait fails is marked timed_out). Returns the
  // indices of the new bots.
  std::vector<std::size_t> launch(std::size_t n);
  std::vector<std::size_t> launch(std::size_t n, const std::string& behavior_spec);

  // One loop iteration, to be called phases_per_tick() times per server tick (step_period()
  // apart): handles join replies (subscribes accepted bots), join timeouts, new MatchInfo, then
  // ticks the joined bots of this phase and sends their commands.
  void step();
  std::uint32_t phases_per_tick() const;
  double step_period_s() const;  // 1 / (tick_hz * phases_per_tick)

  // Sends a leave for every joined bot (reliable; give it a moment before destroying the fleet).
  void leave_all();

  std::size_t size() const;
  const Bot& bot(std::size_t i) const;
  std::uint32_t tick_hz() const;  // the server's (MatchInfo), 30 until known
  std::shared_ptr<const MatchView> match() const;
  bool server_ended() const;      // MatchInfo or ServerStats said the match ended
  std::optional<protocol::ServerStats> last_server_stats() const;
  std::vector<protocol::ServerStats> server_stats_history() const;
  // Every accepted JoinReply seen (any client's), by arrival.
  std::vector<protocol::JoinReply> accepted_replies() const;
  std::uint64_t send_errors() const;

  FleetProgress progress() const;
  Samples take_window_latency();  // latencies measured since the last call, all bots
  std::vector<BotReport> reports() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace throng::client_sim
