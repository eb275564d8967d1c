#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "match_test_util.h"
#include "throng/match/match.h"
#include "throng/params/object_params.h"
#include "throng/params/push_policy.h"
#include "throng/world/world.h"

namespace throng::match {
namespace {

protocol::ParamUpdate update(std::uint64_t request, std::uint32_t entity, std::string param, double value) {
  protocol::ParamUpdate u;
  u.request_id = request;
  u.entity = entity;
  u.param = std::move(param);
  u.value = value;
  return u;
}

protocol::ParamUpdate policy_update(std::uint64_t request, std::string json) {
  protocol::ParamUpdate u;
  u.request_id = request;
  u.policy_json = std::move(json);
  return u;
}

std::uint32_t some_body(const Match& m, std::size_t dense = 3) { return m.world().id_at(dense).value; }

TEST(MatchParams, AppliedUpdateChangesTheWorldAndBumpsTheVersion) {
  Match m(test::two_armies(), test::small_config(), "m");
  Outbox out;
  m.tick(out);
  const std::uint32_t e = some_body(m);
  m.inputs().push(update(7, e, "weight", 250.0));
  const TickReport& r = m.tick(out);
  EXPECT_EQ(r.param_updates_applied, 1u);
  ASSERT_EQ(out.param_replies.size(), 1u);
  EXPECT_TRUE(out.param_replies[0].ok) << out.param_replies[0].error;
  EXPECT_EQ(out.param_replies[0].request_id, 7u);
  EXPECT_EQ(out.param_replies[0].param_version, 1u);
  EXPECT_EQ(out.param_replies[0].tick, 2u);
  EXPECT_TRUE(out.match_info_changed);
  EXPECT_EQ(m.match_info().param_version, 1u);
  EXPECT_DOUBLE_EQ(m.world().params(ObjectId{e}).weight_kg, 250.0);

  // Faction change: the roster follows.
  m.inputs().push(update(8, e, "faction", 2));
  m.tick(out);
  ASSERT_TRUE(out.param_replies[0].ok) << out.param_replies[0].error;
  EXPECT_EQ(m.match_info().param_version, 2u);
  EXPECT_EQ(m.match_info().roster.faction[3], 2);

  // Scenery softness: the match info's scenery follows.
  const std::uint32_t bush = m.match_info().scenery[1].id;
  m.inputs().push(update(9, bush, "softness", 0.25));
  m.tick(out);
  ASSERT_TRUE(out.param_replies[0].ok) << out.param_replies[0].error;
  EXPECT_FLOAT_EQ(m.match_info().scenery[1].softness, 0.25f);

  // Without updates the match info is not republished.
  m.tick(out);
  EXPECT_FALSE(out.match_info_changed);
}

TEST(MatchParams, PolicyReplacementUpdatesTheHash) {
  Match m(test::two_armies(), test::small_config(), "m");
  Outbox out;
  const std::uint64_t before = m.match_info().push_policy_hash;
  m.inputs().push(policy_update(1, R"({"mode": "half"})"));
  m.tick(out);
  ASSERT_EQ(out.param_replies.size(), 1u);
  ASSERT_TRUE(out.param_replies[0].ok) << out.param_replies[0].error;
  EXPECT_EQ(m.world().policy().mode(), params::PushMode::half);
  EXPECT_NE(m.match_info().push_policy_hash, before);
  const std::uint64_t half = m.match_info().push_policy_hash;
  // The same policy with other whitespace hashes the same.
  m.inputs().push(policy_update(2, "{ \"mode\" :\n \"half\" }"));
  m.tick(out);
  ASSERT_TRUE(out.param_replies[0].ok);
  EXPECT_EQ(m.match_info().push_policy_hash, half);
  EXPECT_EQ(m.match_info().param_version, 2u);
}

// Every rejected update: error message, version unchanged, world identical to a twin that never
// received it.
TEST(MatchParams, RejectedUpdatesLeaveTheWorldUnchanged) {
  Match m(test::two_armies(), test::small_config(), "m");
  Match twin(test::two_armies(), test::small_config(), "twin");
  Outbox out, twin_out;
  m.tick(out);
  twin.tick(twin_out);
  const std::uint32_t e = some_body(m);
  const std::uint64_t policy_hash = m.match_info().push_policy_hash;
  struct Case {
    protocol::ParamUpdate u;
    const char* expect_in_error;
  };
  std::vector<Case> cases;
  cases.push_back({update(1, e, "wieght", 100.0), "unknown parameter 'wieght'"});
  cases.push_back({update(2, e, "weight_kg", std::numeric_limits<double>::quiet_NaN()), "weight"});
  cases.push_back({update(3, e, "importance", 11.0), "importance"});
  cases.push_back({update(4, 0xABCDEFu, "weight_kg", 90.0), "unknown entity"});
  cases.push_back({update(5, 0, "weight_kg", 90.0), "unknown entity"});
  cases.push_back({policy_update(6, "{\"mode\": "), ""});                       // malformed JSON
  cases.push_back({policy_update(7, R"({"mode": "sideways"})"), "mode"});        // unknown mode
  cases.push_back({policy_update(8, R"({"mode": "ratio", "terms": [{"param": "weight", "scale": -1}]})"), "scale"});
  protocol::ParamUpdate both = policy_update(9, R"({"mode": "half"})");
  both.entity = e;
  cases.push_back({both, "policy_json"});
  for (const Case& c : cases) {
    m.inputs().push(protocol::ParamUpdate(c.u));
    const TickReport& r = m.tick(out);
    twin.tick(twin_out);
    EXPECT_EQ(r.param_updates_rejected, 1u) << c.u.request_id;
    ASSERT_EQ(out.param_replies.size(), 1u);
    const protocol::ParamReply& reply = out.param_replies[0];
    EXPECT_FALSE(reply.ok) << c.u.request_id;
    EXPECT_EQ(reply.request_id, c.u.request_id);
    EXPECT_FALSE(reply.error.empty());
    EXPECT_NE(reply.error.find(c.expect_in_error), std::string::npos) << reply.error;
    EXPECT_EQ(reply.param_version, 0u);
    EXPECT_FALSE(out.match_info_changed);
    EXPECT_EQ(r.state_hash, twin.state_hash()) << c.u.request_id;
  }
  EXPECT_EQ(m.match_info().param_version, 0u);
  EXPECT_EQ(m.match_info().push_policy_hash, policy_hash);
  EXPECT_DOUBLE_EQ(m.world().params(ObjectId{e}).weight_kg, twin.world().params(ObjectId{e}).weight_kg);
  for (int t = 0; t < 30; ++t) EXPECT_EQ(m.tick(out).state_hash, twin.tick(twin_out).state_hash);
}

TEST(MatchParams, OperatorChangeOnAControlledEntitySurvivesTheLeave) {
  Match m(test::two_armies(), test::small_config(), "m");
  Outbox out;
  const protocol::JoinReply j = test::join_one(m, out, 1);
  m.inputs().push(update(1, j.entity, "importance", 3.0));
  m.tick(out);
  ASSERT_TRUE(out.param_replies[0].ok) << out.param_replies[0].error;
  EXPECT_DOUBLE_EQ(m.world().params(ObjectId{j.entity}).importance, 3.0);
  m.inputs().push(test::leave_request(1, j.client_id));
  m.tick(out);
  EXPECT_DOUBLE_EQ(m.world().params(ObjectId{j.entity}).importance, 3.0);
}

}  // namespace
}  // namespace throng::match
