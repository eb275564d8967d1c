// InputQueue: listener threads push, the tick thread drains once per tick.
//
// Determinism: drain() sorts by the full content of each message (floats compared by their bit
// patterns, so NaN cannot break the strict weak order), so two messages that compare equal are
// identical and the order they arrived in can never show. The keys the match relies on come
// first: joins by (client_nonce, leave), commands by (entity, sequence, client_id), parameter
// updates by request_id.
//
// Bound: each kind (joins, commands, parameter updates) holds at most max_pending messages between
// two drains; further pushes of that kind are dropped and counted.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <tuple>
#include <utility>

#include "throng/match/input_queue.h"

namespace throng::match {
namespace {

std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }
std::uint64_t bits(double d) { return std::bit_cast<std::uint64_t>(d); }

bool join_less(const protocol::JoinRequest& a, const protocol::JoinRequest& b) {
  return std::tie(a.client_nonce, a.leave, a.client_id, a.protocol_version, a.name, a.sender, a.identity) <
         std::tie(b.client_nonce, b.leave, b.client_id, b.protocol_version, b.name, b.sender, b.identity);
}

auto command_key(const protocol::Command& c) {
  return std::make_tuple(c.entity, c.sequence, c.client_id, c.last_seen_tick, bits(c.move_x), bits(c.move_y),
                         bits(c.facing_rad), c.actions, bits(c.camera_x), bits(c.camera_y), bits(c.camera_z),
                         c.sender);
}

bool command_less(const protocol::Command& a, const protocol::Command& b) { return command_key(a) < command_key(b); }

bool param_less(const protocol::ParamUpdate& a, const protocol::ParamUpdate& b) {
  const std::uint64_t va = bits(a.value);
  const std::uint64_t vb = bits(b.value);
  return std::tie(a.request_id, a.entity, a.param, va, a.policy_json, a.sender) <
         std::tie(b.request_id, b.entity, b.param, vb, b.policy_json, b.sender);
}

template <class T, class V>
bool push_bounded(V& v, T&& item, std::size_t max_pending, std::size_t& dropped) {
  if (v.size() >= max_pending) {
    ++dropped;
    return false;
  }
  v.push_back(std::forward<T>(item));
  return true;
}

}  // namespace

void InputQueue::push(protocol::JoinRequest&& r) {
  std::lock_guard<std::mutex> lock(mutex_);
  push_bounded(pending_.joins, std::move(r), max_pending_, dropped_);
}

void InputQueue::push(protocol::Command&& c) {
  std::lock_guard<std::mutex> lock(mutex_);
  push_bounded(pending_.commands, std::move(c), max_pending_, dropped_);
}

void InputQueue::push(protocol::ParamUpdate&& u) {
  std::lock_guard<std::mutex> lock(mutex_);
  push_bounded(pending_.params, std::move(u), max_pending_, dropped_);
}

void InputQueue::drain(TickInputs& out) {
  // Clear first so the vectors handed back to pending_ keep their capacity (no allocation once
  // the queue has seen its busiest tick).
  out.clear();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::swap(out.joins, pending_.joins);
    std::swap(out.commands, pending_.commands);
    std::swap(out.params, pending_.params);
  }
  std::sort(out.joins.begin(), out.joins.end(), join_less);
  std::sort(out.commands.begin(), out.commands.end(), command_less);
  std::sort(out.params.begin(), out.params.end(), param_less);
}

std::size_t InputQueue::dropped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_;
}

}  // namespace throng::match
