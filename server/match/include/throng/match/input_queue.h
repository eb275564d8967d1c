#pragma once
// The only door from the network into the simulation. DDS listener threads push; the tick thread
// drains once per tick and sorts what it got into a deterministic order (joins by nonce, commands
// by (entity, sequence), parameter updates by request id), so the order packets arrived in never
// changes the simulation.
#include <cstddef>
#include <mutex>
#include <vector>

#include "throng/protocol/messages.h"

namespace throng::match {

struct TickInputs {
  std::vector<protocol::JoinRequest> joins;
  std::vector<protocol::Command> commands;
  std::vector<protocol::ParamUpdate> params;
  void clear() { joins.clear(); commands.clear(); params.clear(); }
};

class InputQueue {
 public:
  // Bounded so a flood cannot grow memory without limit: beyond max_pending commands per tick,
  // pushes are dropped and counted (dropped()).
  explicit InputQueue(std::size_t max_pending = 65536) : max_pending_(max_pending) {}
  void push(protocol::JoinRequest&& r);
  void push(protocol::Command&& c);
  void push(protocol::ParamUpdate&& u);
  // Swaps the pending inputs into out (out's previous contents are discarded) and sorts them.
  void drain(TickInputs& out);
  std::size_t dropped() const;

 private:
  mutable std::mutex mutex_;
  TickInputs pending_;
  std::size_t max_pending_;
  std::size_t dropped_ = 0;
};

}  // namespace throng::match
