#pragma once
// Every client the match ever had, for the end-of-match summary: the match itself only knows the
// connected ones. Filled from the match's client events and the publish loop.
#include <cstdint>
#include <map>
#include <string>

#include "throng/match/match.h"

namespace throng::server {

struct ClientRecord {
  std::uint32_t client_id = 0;
  std::string name;
  std::uint32_t entity = 0;
  std::uint64_t joined_tick = 0;
  std::uint64_t departed_tick = 0;  // 0 while connected
  std::string departure;            // "", "left", "timed_out"
  std::uint64_t snapshots_published = 0;
  std::uint64_t poses_published = 0;
  std::uint64_t commands_accepted = 0;
  std::uint64_t commands_rejected = 0;
};

class ClientLedger {
 public:
  void joined(const match::ClientEvent& e, std::uint64_t tick);
  void departed(const match::ClientEvent& e, std::uint64_t tick);
  void snapshot_published(std::uint32_t client_id, std::size_t poses);
  // Copies the match's per-client command counts for the clients still connected (departed ones
  // got theirs from their departure event). Allocates: for the end of the match, not every tick.
  void update_commands(const match::Match& match);
  const std::map<std::uint32_t, ClientRecord>& records() const { return records_; }

 private:
  std::map<std::uint32_t, ClientRecord> records_;  // ordered by client id: deterministic output
};

}  // namespace throng::server
