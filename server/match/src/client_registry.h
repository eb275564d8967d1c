#pragma once
// The clients of one match: ids from 1, never reused; lookups by id (dense, O(1)) and by nonce
// (connected clients only); the connected ids in ascending order (the snapshot and camera order).
#include <cstdint>
#include <deque>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "throng/core/object_id.h"
#include "throng/core/vec3.h"
#include "throng/protocol/messages.h"

namespace throng::match {

// protocol::kIdentityPartitionPrefix + identity + "_" + id when the join carried an authenticated
// identity (DDS Security), else c<client id>.
std::string client_partition(std::uint32_t id, const std::string& identity);

struct ClientRecord {
  std::uint32_t id = 0;
  std::uint64_t nonce = 0;
  std::string name;
  std::string partition;
  // The participant that joined this client: only it may command the client or make it leave.
  protocol::ParticipantKey owner;
  ObjectId entity;
  std::uint8_t faction = 0;
  bool connected = false;
  std::uint64_t joined_tick = 0;
  std::uint64_t last_activity_tick = 0;  // join or last accepted command
  std::uint32_t last_applied_sequence = 0;
  std::uint64_t last_applied_tick = 0;
  std::uint64_t rate_tick = 0;           // the tick accepted_in_tick counts for
  std::uint32_t accepted_in_tick = 0;
  bool has_camera = false;               // false until the first accepted command
  Vec3 camera;
  // The entity's parameters as an NPC, restored when the client lets go of it.
  double npc_character_type = 1.0;
  double npc_importance = 1.0;
  double base_weight_kg = 80.0;          // unbraced weight; kActionBrace doubles it while held
  bool bracing = false;
  // Commands carrying this client's id, by outcome (for the summary and the bots' cross-check).
  std::uint64_t commands_accepted = 0;
  std::uint64_t commands_rejected = 0;
};

class ClientRegistry {
 public:
  // A new connected client with the next id, owned by `owner`, its partition named from
  // `identity` (client_partition). The reference stays valid (deque).
  ClientRecord& add(std::uint64_t nonce, std::string name, const protocol::ParticipantKey& owner,
                    const std::string& identity);
  // Any client ever seen (connected or not); nullptr for an id never given out.
  ClientRecord* find(std::uint32_t id);
  const ClientRecord* find(std::uint32_t id) const;
  ClientRecord* find_connected(std::uint32_t id);
  ClientRecord* find_connected_nonce(std::uint64_t nonce);
  void disconnect(std::uint32_t id);

  std::span<const std::uint32_t> connected_ids() const { return connected_; }
  std::size_t connected_count() const { return connected_.size(); }
  std::uint32_t next_id() const { return static_cast<std::uint32_t>(records_.size()) + 1u; }

  // Checkpoints: every client ever seen, index = id - 1. restore() replaces them and rebuilds the
  // connected list and the nonce index the same way add() / disconnect() leave them.
  const std::deque<ClientRecord>& records() const { return records_; }
  void restore(std::deque<ClientRecord> records);

 private:
  std::deque<ClientRecord> records_;  // index = id - 1
  std::vector<std::uint32_t> connected_;  // ascending
  std::map<std::uint64_t, std::uint32_t> by_nonce_;  // connected clients only
};

}  // namespace throng::match
