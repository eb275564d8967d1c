#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "match_test_util.h"
#include "throng/match/match.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"

namespace throng::match {
namespace {

// The inputs of one tick, made from a seeded generator (the same for every run).
struct TickPlan {
  std::vector<protocol::JoinRequest> joins;
  std::vector<protocol::Command> commands;
  std::vector<protocol::ParamUpdate> params;
};

std::vector<TickPlan> make_plan(int ticks, const std::vector<std::uint32_t>& entities) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::vector<TickPlan> plan(static_cast<std::size_t>(ticks));
  for (std::uint64_t n = 1; n <= 6; ++n) plan[n].joins.push_back(test::join_request(1000 + n, "bot"));
  std::vector<std::uint32_t> seq(7, 0);
  for (int t = 8; t < ticks; ++t) {
    for (std::uint32_t c = 1; c <= 6; ++c) {
      if (c == 6 && t > 100) continue;  // client 6 goes silent (times out)
      if (c == 5 && t >= 200) continue;  // client 5 leaves at tick 200
      if (rng() % 3 == 0) continue;
      const std::uint32_t count = 1 + static_cast<std::uint32_t>(rng() % 6);  // sometimes over the rate limit
      for (std::uint32_t k = 0; k < count; ++k) {
        protocol::Command cmd = test::command(c, entities[c], ++seq[c], 0.7f * unit(rng), 0.7f * unit(rng));
        cmd.facing_rad = 3.0f * unit(rng);
        cmd.camera_x = 10.0f * unit(rng);
        cmd.camera_y = 10.0f * unit(rng);
        if (rng() % 7 == 0) cmd.actions = protocol::kActionSprint;
        if (rng() % 11 == 0) cmd.actions = protocol::kActionBrace;
        if (rng() % 13 == 0) cmd.move_x = 3.0f;                 // rejected
        if (rng() % 17 == 0) cmd.sequence = seq[c] - 1;         // stale / duplicate
        plan[t].commands.push_back(cmd);
      }
    }
  }
  plan[200].joins.push_back(test::leave_request(1005, 5));
  protocol::ParamUpdate u;
  u.request_id = 1;
  u.entity = entities[1];
  u.param = "weight_kg";
  u.value = 300.0;
  plan[50].params.push_back(u);
  protocol::ParamUpdate p;
  p.request_id = 2;
  p.policy_json = R"({"mode": "ratio", "terms": [{"param": "weight", "scale": 50}, {"param": "camera_distance_m", "scale": 200}]})";
  plan[120].params.push_back(p);
  return plan;
}

scene::SceneDef small_battle() { return scene::scale_scene(scene::builtin_scene("battle"), 300); }

// Entities the six clients will get: found by a dry run (the takeover is deterministic).
std::vector<std::uint32_t> client_entities() {
  Match m(small_battle(), test::small_config(), "probe");
  Outbox out;
  std::vector<std::uint32_t> e(7, 0);
  m.tick(out);  // the plan's joins start at its second tick
  for (std::uint64_t n = 1; n <= 6; ++n) {
    m.inputs().push(test::join_request(1000 + n, "bot"));
    m.tick(out);
    e[n] = out.join_replies.at(0).entity;
  }
  return e;
}

std::vector<std::uint64_t> run(const std::vector<TickPlan>& plan, std::uint64_t shuffle_seed) {
  Match m(small_battle(), test::small_config(), "det");
  Outbox out;
  std::mt19937_64 rng(shuffle_seed);
  std::vector<std::uint64_t> hashes;
  for (const TickPlan& tp : plan) {
    TickPlan copy = tp;
    if (shuffle_seed != 0) {
      std::shuffle(copy.joins.begin(), copy.joins.end(), rng);
      std::shuffle(copy.commands.begin(), copy.commands.end(), rng);
      std::shuffle(copy.params.begin(), copy.params.end(), rng);
    }
    const bool joining = !copy.joins.empty();
    for (auto& j : copy.joins) m.inputs().push(std::move(j));
    for (auto& c : copy.commands) m.inputs().push(std::move(c));
    for (auto& p : copy.params) m.inputs().push(std::move(p));
    const TickReport& r = m.tick(out);
    hashes.push_back(r.state_hash);
    if (joining && r.tick <= 7) {
      EXPECT_EQ(r.joins_accepted, 1u);
    }
    // Fold in what the clients are told, so the outputs are compared too.
    std::uint64_t h = r.state_hash;
    for (std::size_t k = 0; k < out.snapshot_count; ++k) {
      const protocol::Snapshot& s = out.snapshots[k];
      h = h * 1099511628211ull ^ s.last_applied_sequence;
      h = h * 1099511628211ull ^ s.id_codes.size();
      for (auto v : s.x) h = h * 1099511628211ull ^ static_cast<std::uint16_t>(v);
    }
    hashes.push_back(h);
  }
  EXPECT_EQ(m.client_count(), 4u);  // 6 joined, one left, one timed out
  EXPECT_GT(m.commands_accepted_total(), 500u);
  std::uint64_t rejected = 0;
  for (auto n : m.rejected_by_reason()) rejected += n;
  EXPECT_GT(rejected, 50u);
  return hashes;
}

TEST(MatchDeterminism, SameInputsSameHashesEveryTick) {
  const auto plan = make_plan(300, client_entities());
  const auto a = run(plan, 0);
  const auto b = run(plan, 0);
  const auto shuffled = run(plan, 99);  // arrival order within a tick must not matter
  ASSERT_EQ(a.size(), 600u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i], b[i]) << "tick " << i / 2 + 1;
    ASSERT_EQ(a[i], shuffled[i]) << "tick " << i / 2 + 1;
  }
}

}  // namespace
}  // namespace throng::match
