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
  ClientRecord& r = records_.emplace_back();
  r.id = static_cast<std::uint32_t>(records_.size());
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
  if (id == 0 || id > records_.size()) return nullptr;
  return &records_[id - 1];
}

const ClientRecord* ClientRegistry::find(std::uint32_t id) const {
  if (id == 0 || id > records_.size()) return nullptr;
  return &records_[id - 1];
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
  auto it = std::lower_bound(connected_.begin(), connected_.end(), id);
  if (it != connected_.end() && *it == id) connected_.erase(it);
  auto n = by_nonce_.find(r->nonce);
  if (n != by_nonce_.end() && n->second == id) by_nonce_.erase(n);
}

void ClientRegistry::restore(std::deque<ClientRecord> records) {
  records_ = std::move(records);
  connected_.clear();
  by_nonce_.clear();
  for (const ClientRecord& r : records_) {
    if (!r.connected) continue;
    connected_.push_back(r.id);  // records are in id order: stays sorted
    by_nonce_[r.nonce] = r.id;   // a later client with the same nonce wins, as in add()
  }
}

}  // namespace throng::match
