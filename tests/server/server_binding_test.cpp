// A client belongs to the DDS participant that joined it, and only operators change parameters:
// the attacks of a second participant on the match's domain (an attacker with the project's own
// ClientTransport, no join) fail while the victim keeps playing. (Reading another player's
// snapshot partition can only be stopped with DDS Security: tests/server/server_security_test.cpp.)
#include <gtest/gtest.h>

#include "server_test_support.h"

namespace throng::test {
namespace {

TEST(ServerBinding, AnotherParticipantCannotCommandOrKickAClient) {
  auto options = small_server_options(158);
  nlohmann::json summary;
  {
    ServerThread server(options);
    TestClient victim(158);
    const auto r = victim.join(9001, "victim");
    ASSERT_TRUE(r && r->result == protocol::JoinResult::accepted);
    victim.transport().send_command(standing_command(*r, 1));
    ASSERT_TRUE(victim.wait_until([&] { return !victim.snapshots().empty() && victim.snapshots().back().last_applied_sequence == 1; }));

    // The attacker learns everything from the public join reply: id, entity, nonce.
    TestClient attacker(158);
    ASSERT_TRUE(attacker.transport().wait_for_server(10s));
    ASSERT_TRUE(wait_for_command_writers(server, 2));
    ASSERT_TRUE(attacker.wait_until([&] {
      for (const auto& x : attacker.replies())
        if (x.client_nonce == 9001) return true;
      return false;
    }));
    hijack_and_kick(attacker.transport(), *r, 20, 1000);

    // The victim still controls its character: its next sequence is applied.
    victim.transport().send_command(standing_command(*r, 2));
    EXPECT_TRUE(victim.wait_until([&] { return !victim.snapshots().empty() && victim.snapshots().back().last_applied_sequence == 2; }))
        << "last applied " << victim.with_lock([&] { return last_applied(victim.snapshots(), r->client_id); });
    const bool told_left = victim.with_lock([&] {
      for (const auto& x : victim.replies())
        if (x.client_nonce == 9001 && x.result != protocol::JoinResult::accepted) return true;
      return false;
    });
    EXPECT_FALSE(told_left) << "a reply to the forged leave replaced the victim's own";
    server.stop();
    summary = server.server().summary();
  }
  EXPECT_EQ(summary["rejected_by_reason"]["foreign_participant"], 20) << summary.dump(2);
  EXPECT_EQ(summary["rejected_by_reason"]["stale_sequence"], 0);
  EXPECT_EQ(summary["joins_foreign_participant"], 1);
  EXPECT_EQ(summary["clients_connected_at_end"], 1);
  EXPECT_EQ(summary["commands_accepted"], 2);
}

// One parameter change from a participant on a server without --security: refused unless the
// server allows anonymous operators.
protocol::ParamReply change_weight(int domain, bool allow_anonymous, nlohmann::json& summary) {
  auto options = small_server_options(domain);
  options.allow_anonymous_operator = allow_anonymous;
  ServerThread server(options);
  TestClient op(domain);
  EXPECT_TRUE(op.transport().wait_for_server(10s));
  EXPECT_TRUE(op.wait_until([&] { return !op.match_infos().empty(); }));
  const std::uint32_t entity = op.with_lock([&] { return op.match_infos().back().roster.id.at(0); });
  protocol::ParamUpdate u;
  u.request_id = 77;
  u.entity = entity;
  u.param = "weight";
  u.value = 2500.0;
  op.transport().send_param_update(u);
  protocol::ParamReply reply;
  EXPECT_TRUE(op.wait_until([&] {
    if (op.param_replies().empty()) return false;
    reply = op.param_replies().back();
    return true;
  }));
  std::this_thread::sleep_for(100ms);
  const std::uint32_t version = op.with_lock([&] { return op.match_infos().back().param_version; });
  EXPECT_EQ(version, allow_anonymous ? 1u : 0u) << "param_version after the change";
  server.stop();
  summary = server.server().summary();
  return reply;
}

TEST(ServerBinding, ParameterChangesNeedAnOperator) {
  nlohmann::json summary;
  const protocol::ParamReply refused = change_weight(154, false, summary);
  EXPECT_EQ(refused.request_id, 77u);
  EXPECT_FALSE(refused.ok);
  EXPECT_EQ(refused.error, "not an operator");
  EXPECT_EQ(summary["param_updates_not_operator"], 1);

  const protocol::ParamReply applied = change_weight(155, true, summary);
  EXPECT_EQ(applied.request_id, 77u);
  EXPECT_TRUE(applied.ok) << applied.error;
  EXPECT_EQ(summary["param_updates_not_operator"], 0);
}

}  // namespace
}  // namespace throng::test
