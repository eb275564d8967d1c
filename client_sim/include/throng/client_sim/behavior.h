#pragma once
// What drives a bot's entity. Once per tick the bot calls act() with what it knows (its
// ClientWorld, its own pose, the other clients' entities) and a sink; the behavior emits zero or
// more commands through the sink. The bot prefills every command (client id, own entity, next
// sequence, last seen tick, camera at the own entity) from the behavior's Intent; misbehaviours
// then spoil the fields they attack (NaN moves, someone else's entity, an old sequence number).
//
// Honest: wander, charge, waypoints, idle. Misbehaviours (security tests; every spoiled command
// must be rejected by the server and change nothing): nan, flood, hijack, stale.
#include <cstdint>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "throng/client_sim/client_world.h"
#include "throng/protocol/messages.h"

namespace throng::client_sim {

// Desired motion: move as a fraction of max speed (|move| <= 1), facing in [-pi, pi].
struct Intent {
  float move_x = 0, move_y = 0, facing_rad = 0;
  std::uint32_t actions = 0;
};

struct BehaviorContext {
  const ClientWorld& world;
  std::uint32_t client_id = 0;
  std::uint32_t entity = 0;
  std::uint8_t faction = 0;
  ObjectState self;              // newest own pose (unquantized)
  ObjectState spawn;             // own pose in the first snapshot
  double time_s = 0;             // since the first snapshot
  std::uint32_t tick_hz = 30;
  std::mt19937_64& rng;
  std::span<const std::uint32_t> other_client_entities;  // from other clients' JoinReplies
};

// What the server is expected to do with a command (bookkeeping only; never sent).
enum class Expect : std::uint8_t {
  accept,   // honest: counted, and its command-to-applied latency is measured
  reject,   // spoiled: the server must reject it
  unknown,  // honest content, but the server may refuse it (e.g. beyond the per-tick rate limit)
};

class CommandSink {
 public:
  virtual ~CommandSink() = default;
  // Appends a prefilled command with the next sequence number and returns it for the behavior
  // to spoil. The reference is valid until the next emit().
  virtual protocol::Command& emit(const Intent& intent, Expect expect = Expect::accept) = 0;
};

class Behavior {
 public:
  virtual ~Behavior() = default;
  virtual std::string_view name() const = 0;
  virtual void act(const BehaviorContext& ctx, CommandSink& out) = 0;
};

// Throws std::invalid_argument for an unknown name.
std::unique_ptr<Behavior> make_behavior(std::string_view name);
const std::vector<std::string>& behavior_names();  // every valid single name
bool is_misbehavior(std::string_view name);

// "wander" -> {"wander"}; "nan,flood" -> {"nan","flood"}; "mix" -> the honest behaviors
// {"wander","charge","waypoints","idle"}. Bot i gets entry i % size. Throws std::invalid_argument
// on an unknown or empty name.
std::vector<std::string> expand_behavior_spec(std::string_view spec);

}  // namespace throng::client_sim
