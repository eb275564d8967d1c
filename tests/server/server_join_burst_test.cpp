// A burst of 1,000 join requests within one second (a bot farm, a reconnect storm): the server
// keeps ticking for the player already in, accepts up to --max-clients, refuses the rest with a
// reply that says why, and afterwards takes a new player as soon as a seat is free. What is lost:
// nothing; the refused joins are answered.
#include <gtest/gtest.h>

#include <map>
#include <thread>

#include "server_test_support.h"

namespace throng::test {
namespace {

using namespace std::chrono_literals;

TEST(ServerJoinBurst, AThousandJoinsInASecondAreAnsweredAndTheMatchGoesOn) {
  auto o = small_server_options(195);
  o.match.max_clients = 16;
  ServerThread server(o);
  TestClient player(195);
  const auto first = player.join(1, "first");
  ASSERT_TRUE(first && first->result == protocol::JoinResult::accepted);
  ASSERT_TRUE(player.wait_until([&] { return player.snapshots().size() >= 3; }));
  const std::uint32_t tick_before = player.with_lock([&] { return player.snapshots().back().tick; });

  TestClient storm(195);
  ASSERT_TRUE(storm.transport().wait_for_server(10s));
  constexpr std::uint64_t kJoins = 1000;
  for (std::uint64_t k = 0; k < kJoins; ++k) {
    protocol::JoinRequest r;
    r.client_nonce = 1000 + k;
    r.name = "storm";
    storm.transport().send_join(r);
    if (k % 34 == 33) std::this_thread::sleep_for(30ms);  // ~1,000 in one second
  }
  // Every join is answered: 15 more seats, the rest refused as full with a reason.
  // The reply topic carries every client's replies: keep the storm's, the first one per nonce.
  auto answered = [&] {
    std::map<std::uint64_t, protocol::JoinReply> first_reply;
    for (const auto& x : storm.replies())
      if (x.client_nonce >= 1000 && x.client_nonce < 1000 + kJoins) first_reply.emplace(x.client_nonce, x);
    return first_reply;
  };
  EXPECT_TRUE(storm.wait_until([&] { return answered().size() == kJoins; }, 30s))
      << storm.with_lock([&] { return answered().size(); }) << " of " << kJoins << " joins answered";
  const auto replies = storm.with_lock(answered);
  std::size_t accepted = 0, full = 0;
  for (const auto& [nonce, reply] : replies) {
    if (reply.result == protocol::JoinResult::accepted) ++accepted;
    if (reply.result == protocol::JoinResult::match_full) {
      ++full;
      EXPECT_FALSE(reply.reason.empty()) << "a refusal must say why";
    }
  }
  EXPECT_EQ(accepted, 15u);
  EXPECT_EQ(full, replies.size() - accepted);

  // The player already in kept getting snapshots through the storm.
  ASSERT_TRUE(player.wait_until([&] { return player.snapshots().back().tick > tick_before + 30; }, 10s));

  // One seat freed: the next join takes it.
  ASSERT_TRUE(player.leave(1, first->client_id)) << "no reply to the leave";
  TestClient late(195);
  const auto r = late.join(5000, "late");
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->result, protocol::JoinResult::accepted) << r->reason;
}

}  // namespace
}  // namespace throng::test
