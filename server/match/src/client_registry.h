#pragma once
// The clients of one match: ids from 1, never reused; lookups by id and by nonce; the connected ids
// in ascending order (the snapshot and camera order). Only connected clients are kept: a departed
// client's record goes at the end of the tick it left in (forget_departed), so that a match hosting
// joins and leaves for hours holds memory for the clients it has, not for every client it had.
// What a departed client leaves behind is its departure event (ClientEvent), which carries its
// command counts to the server's summary.
#include <cstdint>
#include <map>
#include <string>
#include <span>
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
  // `identity` (client_partition). The reference stays valid until the record is forgotten.
  ClientRecord& add(std::uint64_t nonce, std::string name, const protocol::ParticipantKey& owner,
                    const std::string& identity);
  // A connected client, or one that disconnected since the last forget_departed(); nullptr else.
  ClientRecord* find(std::uint32_t id);
  const ClientRecord* find(std::uint32_t id) const;
  ClientRecord* find_connected(std::uint32_t id);
  ClientRecord* find_connected_nonce(std::uint64_t nonce);
  // The record stays readable (find) until forget_departed(): the tick that disconnects a client
  // still reports its departure from it.
  void disconnect(std::uint32_t id);
  // Drops the records of the clients disconnected since the last call (the match's tick ends with it).
  void forget_departed();
  // An id given out before (connected or departed), as opposed to one never seen.
  bool was_given_out(std::uint32_t id) const { return id != 0 && id < next_id_; }

  std::span<const std::uint32_t> connected_ids() const { return connected_; }
  std::size_t connected_count() const { return connected_.size(); }
  std::uint32_t next_id() const { return next_id_; }

  // Checkpoints: the records held (between ticks: the connected clients), in id order. restore()
  // replaces them and rebuilds the connected list and the nonce index as add() leaves them. The
  // caller (the checkpoint's decoder) has checked that every record is connected, with ascending
  // ids below next_id.
  const std::map<std::uint32_t, ClientRecord>& records() const { return records_; }
  void restore(std::uint32_t next_id, std::vector<ClientRecord> connected);

 private:
  std::map<std::uint32_t, ClientRecord> records_;  // by id; node-based: add()'s reference survives other adds
  std::vector<std::uint32_t> connected_;  // ascending
  std::vector<std::uint32_t> departed_;   // disconnected since the last forget_departed()
  std::map<std::uint64_t, std::uint32_t> by_nonce_;  // connected clients only
  std::uint32_t next_id_ = 1;
};

}  // namespace throng::match
