#include "throng/server/client_ledger.h"

namespace throng::server {

void ClientLedger::joined(const match::ClientEvent& e, std::uint64_t tick) {
  ClientRecord& r = records_[e.client_id];
  r.client_id = e.client_id;
  r.name = e.name;
  r.entity = e.entity;
  r.joined_tick = tick;
}

void ClientLedger::departed(const match::ClientEvent& e, std::uint64_t tick) {
  auto it = records_.find(e.client_id);
  if (it == records_.end()) return;
  it->second.departed_tick = tick;
  it->second.departure = e.kind == match::ClientEvent::Kind::left ? "left" : "timed_out";
  it->second.commands_accepted = e.commands_accepted;
  it->second.commands_rejected = e.commands_rejected;
}

void ClientLedger::snapshot_published(std::uint32_t client_id, std::size_t poses) {
  auto it = records_.find(client_id);
  if (it == records_.end()) return;
  ++it->second.snapshots_published;
  it->second.poses_published += poses;
}

void ClientLedger::update_commands(const match::Match& match) {
  for (const auto& c : match.clients()) {
    auto it = records_.find(c.client_id);
    if (it == records_.end()) continue;
    it->second.commands_accepted = c.commands_accepted;
    it->second.commands_rejected = c.commands_rejected;
  }
}

}  // namespace throng::server
