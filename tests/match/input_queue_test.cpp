#include "throng/match/input_queue.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <thread>
#include <tuple>
#include <vector>

namespace throng::match {
namespace {

std::vector<protocol::Command> sample_commands() {
  std::vector<protocol::Command> v;
  for (std::uint32_t e = 3; e >= 1; --e) {
    for (std::uint32_t s = 1; s <= 3; ++s) {
      for (std::uint32_t c = 2; c >= 1; --c) {
        protocol::Command cmd;
        cmd.entity = e;
        cmd.sequence = s;
        cmd.client_id = c;
        cmd.move_x = 0.1f * static_cast<float>(s);
        v.push_back(cmd);
      }
    }
  }
  // Same (entity, sequence, client) with different content, one of them NaN: still a total order.
  protocol::Command a;
  a.entity = 2;
  a.sequence = 2;
  a.client_id = 1;
  a.move_y = std::numeric_limits<float>::quiet_NaN();
  v.push_back(a);
  a.move_y = -0.5f;
  v.push_back(a);
  return v;
}

std::vector<protocol::Command> drained_commands(std::vector<protocol::Command> in, std::uint64_t shuffle_seed) {
  std::mt19937_64 rng(shuffle_seed);
  std::shuffle(in.begin(), in.end(), rng);
  InputQueue q;
  for (auto& c : in) q.push(std::move(c));
  TickInputs out;
  q.drain(out);
  return out.commands;
}

bool same_command(const protocol::Command& a, const protocol::Command& b) {
  auto feq = [](float x, float y) { return (std::isnan(x) && std::isnan(y)) || x == y; };
  return a.entity == b.entity && a.sequence == b.sequence && a.client_id == b.client_id && feq(a.move_x, b.move_x) &&
         feq(a.move_y, b.move_y);
}

TEST(InputQueue, CommandOrderIsIndependentOfPushOrder) {
  const auto first = drained_commands(sample_commands(), 1);
  for (std::uint64_t seed = 2; seed < 12; ++seed) {
    const auto again = drained_commands(sample_commands(), seed);
    ASSERT_EQ(again.size(), first.size());
    for (std::size_t i = 0; i < first.size(); ++i) EXPECT_TRUE(same_command(first[i], again[i])) << "index " << i;
  }
  // Keyed by (entity, sequence, client_id).
  for (std::size_t i = 1; i < first.size(); ++i) {
    const auto& p = first[i - 1];
    const auto& c = first[i];
    EXPECT_LE(std::tie(p.entity, p.sequence, p.client_id), std::tie(c.entity, c.sequence, c.client_id));
  }
  EXPECT_EQ(first.front().entity, 1u);
  EXPECT_EQ(first.front().sequence, 1u);
  EXPECT_EQ(first.front().client_id, 1u);
}

TEST(InputQueue, JoinsAndParamsAreSorted) {
  InputQueue q;
  for (std::uint64_t nonce : {9u, 3u, 7u}) {
    protocol::JoinRequest leave;
    leave.client_nonce = nonce;
    leave.leave = true;
    q.push(std::move(leave));
    protocol::JoinRequest join;
    join.client_nonce = nonce;
    q.push(std::move(join));
  }
  for (std::uint64_t id : {5u, 1u, 4u}) {
    protocol::ParamUpdate u;
    u.request_id = id;
    q.push(std::move(u));
  }
  TickInputs out;
  q.drain(out);
  ASSERT_EQ(out.joins.size(), 6u);
  const std::uint64_t nonces[] = {3, 3, 7, 7, 9, 9};
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(out.joins[i].client_nonce, nonces[i]);
    EXPECT_EQ(out.joins[i].leave, i % 2 == 1);  // join before leave for the same nonce
  }
  ASSERT_EQ(out.params.size(), 3u);
  EXPECT_EQ(out.params[0].request_id, 1u);
  EXPECT_EQ(out.params[1].request_id, 4u);
  EXPECT_EQ(out.params[2].request_id, 5u);
}

TEST(InputQueue, DrainEmptiesTheQueueAndDiscardsOldContents) {
  InputQueue q;
  TickInputs out;
  out.commands.resize(5);
  protocol::Command c;
  c.sequence = 1;
  q.push(protocol::Command(c));
  q.drain(out);
  ASSERT_EQ(out.commands.size(), 1u);
  q.drain(out);
  EXPECT_TRUE(out.commands.empty());
  EXPECT_TRUE(out.joins.empty());
  EXPECT_TRUE(out.params.empty());
}

TEST(InputQueue, BoundDropsAndCounts) {
  InputQueue q(4);
  for (std::uint32_t i = 0; i < 10; ++i) {
    protocol::Command c;
    c.sequence = i;
    q.push(std::move(c));
  }
  EXPECT_EQ(q.dropped(), 6u);
  for (std::uint32_t i = 0; i < 6; ++i) {
    protocol::JoinRequest r;
    r.client_nonce = i + 1;
    q.push(std::move(r));
  }
  EXPECT_EQ(q.dropped(), 8u);
  TickInputs out;
  q.drain(out);
  EXPECT_EQ(out.commands.size(), 4u);
  EXPECT_EQ(out.joins.size(), 4u);
  // The first ones pushed are kept.
  EXPECT_EQ(out.commands.back().sequence, 3u);
  // After a drain there is room again; the drop count is a running total.
  protocol::Command c;
  q.push(std::move(c));
  EXPECT_EQ(q.dropped(), 8u);
  q.drain(out);
  EXPECT_EQ(out.commands.size(), 1u);
}

TEST(InputQueue, ConcurrentPushesAllArrive) {
  InputQueue q;
  constexpr int kThreads = 4;
  constexpr int kPerThread = 500;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&q, t] {
      for (int i = 0; i < kPerThread; ++i) {
        protocol::Command c;
        c.client_id = static_cast<std::uint32_t>(t + 1);
        c.sequence = static_cast<std::uint32_t>(i + 1);
        q.push(std::move(c));
      }
    });
  }
  TickInputs out;
  std::size_t total = 0;
  while (total < kThreads * kPerThread) {
    q.drain(out);
    total += out.commands.size();
    if (out.commands.empty()) std::this_thread::yield();
  }
  for (auto& th : threads) th.join();
  q.drain(out);
  EXPECT_EQ(total + out.commands.size(), static_cast<std::size_t>(kThreads * kPerThread));
  EXPECT_EQ(q.dropped(), 0u);
}

}  // namespace
}  // namespace throng::match
