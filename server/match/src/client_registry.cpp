#include "client_registry.h"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

namespace throng::match {

std::string client_partition(std::uint32_t id, const std::string& identity) {
  return identity.empty() ? fmt::format("c{}", id) : fmt::format("{}{}_{}", protocol::kIdentityPartitionPrefix, identity, id);
}

ClientRecord& ClientRegistry::add(std::uint64_t nonce, std::string name, const protocol::ParticipantKey& owner,
                                  const std::string& identity) {
  const std::uint32_t id = next_id_++;
  ClientRecord& r = records_[id];
  r.id = id;
  r.nonce = nonce;
  r.name = std::move(name);
  r.owner = owner;
  r.partition = client_partition(r.id, identity);
  r.connected = true;
  connected_.push_back(r.id);  // ids only grow: stays sorted
  by_nonce_[nonce] = r.id;
  return r;
}

ClientRecord* ClientRegistry::find(std::uint32_t id) {
  auto it = records_.find(id);
  return it == records_.end() ? nullptr : &it->second;
}

const ClientRecord* ClientRegistry::find(std::uint32_t id) const {
  auto it = records_.find(id);
  return it == records_.end() ? nullptr : &it->second;
}

ClientRecord* ClientRegistry::find_connected(std::uint32_t id) {
  ClientRecord* r = find(id);
  return r != nullptr && r->connected ? r : nullptr;
}

ClientRecord* ClientRegistry::find_connected_nonce(std::uint64_t nonce) {
  auto it = by_nonce_.find(nonce);
  return it == by_nonce_.end() ? nullptr : find_connected(it->second);
}

void ClientRegistry::disconnect(std::uint32_t id) {
  ClientRecord* r = find_connected(id);
  if (r == nullptr) return;
  r->connected = false;
  departed_.push_back(id);
  auto it = std::lower_bound(connected_.begin(), connected_.end(), id);
  if (it != connected_.end() && *it == id) connected_.erase(it);
  auto n = by_nonce_.find(r->nonce);
  if (n != by_nonce_.end() && n->second == id) by_nonce_.erase(n);
}

void ClientRegistry::forget_departed() {
  for (std::uint32_t id : departed_) records_.erase(id);
  departed_.clear();
}

void ClientRegistry::restore(std::uint32_t next_id, std::vector<ClientRecord> connected) {
  records_.clear();
  connected_.clear();
  departed_.clear();
  by_nonce_.clear();
  next_id_ = next_id;
  for (ClientRecord& r : connected) {
    connected_.push_back(r.id);  // in id order: stays sorted
    by_nonce_[r.nonce] = r.id;   // a later client with the same nonce wins, as in add()
    const std::uint32_t id = r.id;
    records_.emplace(id, std::move(r));
  }
}

}  // namespace throng::match
