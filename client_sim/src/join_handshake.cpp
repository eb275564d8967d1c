#include "throng/client_sim/join_handshake.h"

#include <random>
#include <utility>

namespace throng::client_sim {

const char* JoinHandshake::to_string(State s) {
  switch (s) {
    case State::created: return "created";
    case State::joining: return "joining";
    case State::joined: return "joined";
    case State::refused: return "refused";
    case State::timed_out: return "timed_out";
    case State::left: return "left";
  }
  return "?";
}

std::uint64_t JoinHandshake::random_nonce() {
  std::random_device rd;
  std::uint64_t v = 0;
  while (v == 0) v = (static_cast<std::uint64_t>(rd()) << 32) ^ rd();
  return v;
}

JoinHandshake::JoinHandshake(std::uint64_t nonce, std::string name)
    : nonce_(nonce != 0 ? nonce : random_nonce()), name_(std::move(name)) {}

protocol::JoinRequest JoinHandshake::join_request(TimePoint now) {
  if (state_ == State::created) state_ = State::joining;
  if (!join_sent_) join_sent_ = now;
  last_join_sent_ = now;
  protocol::JoinRequest r;
  r.client_nonce = nonce_;
  r.name = name_;
  return r;
}

bool JoinHandshake::on_join_reply(const protocol::JoinReply& reply) {
  if (reply.client_nonce != nonce_ || state_ != State::joining) return false;
  reply_ = reply;
  state_ = reply.result == protocol::JoinResult::accepted ? State::joined : State::refused;
  return state_ == State::joined;
}

std::optional<protocol::JoinRequest> JoinHandshake::leave_request() {
  if (state_ != State::joined) return std::nullopt;
  state_ = State::left;
  protocol::JoinRequest r;
  r.client_nonce = nonce_;
  r.name = name_;
  r.leave = true;
  r.client_id = reply_.client_id;
  return r;
}

void JoinHandshake::mark_timed_out() {
  if (state_ == State::joining || state_ == State::created) state_ = State::timed_out;
}

}  // namespace throng::client_sim
