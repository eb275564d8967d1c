#pragma once
// The client side of the join protocol, which every client follows (the bots, throng-view's
// gateway): a non-zero nonce keys the request and the reply; the owner re-sends the same request
// until the reply for that nonce arrives (the server answers a repeated nonce with its original
// reply); the leave names the client id that reply gave. Not thread-safe: its owner locks if it
// needs to.
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "throng/protocol/messages.h"

namespace throng::client_sim {

class JoinHandshake {
 public:
  using TimePoint = std::chrono::steady_clock::time_point;
  enum class State : std::uint8_t { created, joining, joined, refused, timed_out, left };
  static const char* to_string(State s);
  // A non-zero 64-bit value from std::random_device.
  static std::uint64_t random_nonce();

  // nonce 0 draws one (random_nonce).
  JoinHandshake(std::uint64_t nonce, std::string name);

  // Marks the client joining (from created); called again while joining it returns the same
  // request, a resend. join_sent_at() keeps the first call's time, last_join_sent_at() the latest.
  protocol::JoinRequest join_request(TimePoint now);
  // True when this reply accepted the client now. Replies for other nonces, and replies that come
  // when no join is pending, are ignored (false).
  bool on_join_reply(const protocol::JoinReply& reply);
  // The leave for an accepted client (which is then left); nullopt in any other state.
  std::optional<protocol::JoinRequest> leave_request();
  // A join that was never answered in time (or could not be sent) ends here.
  void mark_timed_out();

  State state() const { return state_; }
  std::uint64_t nonce() const { return nonce_; }
  const std::string& name() const { return name_; }
  const protocol::JoinReply& reply() const { return reply_; }  // the accepted or refusing reply
  std::optional<TimePoint> join_sent_at() const { return join_sent_; }
  std::optional<TimePoint> last_join_sent_at() const { return last_join_sent_; }

 private:
  std::uint64_t nonce_;
  std::string name_;
  State state_ = State::created;
  std::optional<TimePoint> join_sent_, last_join_sent_;
  protocol::JoinReply reply_;
};

}  // namespace throng::client_sim
