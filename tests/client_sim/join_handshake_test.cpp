// The join protocol's client side, shared by the bots and throng-view's gateway.
#include <gtest/gtest.h>

#include "throng/client_sim/join_handshake.h"

namespace throng::client_sim {
namespace {

using State = JoinHandshake::State;
using std::chrono::seconds;

protocol::JoinReply reply_for(std::uint64_t nonce, protocol::JoinResult result) {
  protocol::JoinReply r;
  r.client_nonce = nonce;
  r.result = result;
  r.client_id = 7;
  r.entity = 1234;
  return r;
}

TEST(JoinHandshake, ResendsTheSameRequestUntilItsReplyThenLeavesWithItsClientId) {
  JoinHandshake h(42, "bot-1");
  const JoinHandshake::TimePoint t0{};
  EXPECT_FALSE(h.leave_request());  // nothing to leave yet
  const auto first = h.join_request(t0);
  EXPECT_EQ(h.state(), State::joining);
  const auto again = h.join_request(t0 + seconds(1));
  EXPECT_EQ(first.client_nonce, 42u);
  EXPECT_EQ(again.client_nonce, 42u);
  EXPECT_EQ(again.name, "bot-1");
  EXPECT_FALSE(again.leave);
  EXPECT_EQ(h.join_sent_at(), t0);
  EXPECT_EQ(h.last_join_sent_at(), t0 + seconds(1));

  EXPECT_FALSE(h.on_join_reply(reply_for(43, protocol::JoinResult::accepted)));  // another client's
  EXPECT_EQ(h.state(), State::joining);
  EXPECT_TRUE(h.on_join_reply(reply_for(42, protocol::JoinResult::accepted)));
  EXPECT_EQ(h.state(), State::joined);
  EXPECT_FALSE(h.on_join_reply(reply_for(42, protocol::JoinResult::accepted)));  // a duplicate
  EXPECT_EQ(h.reply().entity, 1234u);

  const auto leave = h.leave_request();
  ASSERT_TRUE(leave);
  EXPECT_TRUE(leave->leave);
  EXPECT_EQ(leave->client_id, 7u);
  EXPECT_EQ(leave->client_nonce, 42u);
  EXPECT_EQ(h.state(), State::left);
  EXPECT_FALSE(h.leave_request());  // once
}

TEST(JoinHandshake, ARefusalIsFinalAndATimeoutEndsOnlyAPendingJoin) {
  JoinHandshake refused(5, "a");
  refused.join_request({});
  EXPECT_FALSE(refused.on_join_reply(reply_for(5, protocol::JoinResult::match_full)));
  EXPECT_EQ(refused.state(), State::refused);
  refused.join_request({});  // a late resend does not reopen it
  EXPECT_EQ(refused.state(), State::refused);
  refused.mark_timed_out();
  EXPECT_EQ(refused.state(), State::refused);

  JoinHandshake pending(6, "b");
  pending.join_request({});
  pending.mark_timed_out();
  EXPECT_EQ(pending.state(), State::timed_out);
  EXPECT_FALSE(pending.on_join_reply(reply_for(6, protocol::JoinResult::accepted)));  // too late
}

TEST(JoinHandshake, AZeroNonceIsDrawnAndNeverZero) {
  for (int i = 0; i < 100; ++i) EXPECT_NE(JoinHandshake(0, "x").nonce(), 0u);
  EXPECT_NE(JoinHandshake(0, "x").nonce(), JoinHandshake(0, "x").nonce());  // 1 in 2^64 to fail
}

}  // namespace
}  // namespace throng::client_sim
