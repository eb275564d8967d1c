// "No allocation in index()/build() after warm-up", checked by counting every operator new in this
// test binary while a moving crowd is indexed and snapshots are built (both build() overloads).
// Counting is off except inside the measured block, so the other suites in the binary are
// unaffected.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <random>
#include <vector>

#include "throng/core/object_id.h"
#include "match_test_util.h"
#include "throng/match/match.h"
#include "throng/match/snapshot_builder.h"
#include "throng/protocol/codec.h"

#include "support/counting_new.h"  // counts operator new while g_counting is set

namespace throng::match {
namespace {

TEST(SnapshotBuilderAllocation, IndexAndBuildDoNotAllocateAfterWarmUp) {
  constexpr double kPi = 3.14159265358979323846;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> pos(-60.0, 60.0), ang(-kPi, kPi);
  std::vector<std::uint32_t> id;
  std::vector<double> x, y, z, heading;
  std::vector<float> yaw;
  for (std::uint32_t i = 0; i < 4000; ++i) {
    id.push_back(ObjectId::make(i, i % 2).value);
    x.push_back(pos(rng));
    y.push_back(pos(rng));
    z.push_back(0.9);
    heading.push_back(ang(rng));
    yaw.push_back(static_cast<float>(heading.back()));
  }
  SnapshotBuilder sb(InterestConfig{});
  for (std::uint32_t c = 1; c <= 4; ++c) sb.add_client(c);
  SnapshotBuilder::Scratch scratch;
  std::vector<protocol::Snapshot> out(4);
  for (auto& s : out) {  // the caller's reused vectors, sized for the largest snapshot
    s.id_codes.reserve(1024);
    s.x.reserve(1024);
    s.y.reserve(1024);
    s.z.reserve(1024);
    s.yaw.reserve(1024);
    s.removed.reserve(1024);
  }
  std::size_t sent = 0;
  auto tick = [&](std::uint64_t t) {
    for (std::size_t i = 0; i < id.size(); ++i) {
      x[i] += 1.5 / 30.0 * std::cos(heading[i]);
      y[i] += 1.5 / 30.0 * std::sin(heading[i]);
    }
    sb.index(BodyView{id, x, y, z, yaw}, t);
    for (std::uint32_t c = 1; c <= 4; ++c) {
      const double cx = 20.0 * std::cos(0.04 * static_cast<double>(t) + c), cy = 20.0 * std::sin(0.04 * t);
      const BuildStats& st = c % 2 ? sb.build(c, cx, cy, out[c - 1]) : sb.build(c, cx, cy, out[c - 1], scratch);
      sent += st.sent;
    }
  };
  std::uint64_t t = 1;
  for (; t <= 30; ++t) tick(t);

  g_allocations = 0;
  g_counting = true;
  { std::vector<int> probe(16); }  // the counter itself works
  g_counting = false;
  ASSERT_EQ(g_allocations.load(), 1u);

  sent = 0;
  g_allocations = 0;
  g_counting = true;
  for (; t <= 90; ++t) tick(t);
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0u);
  EXPECT_GT(sent, 60u * 4u * 50u);
}

// A crowd that keeps spreading out (a routed army fleeing): the interest grid covers more ground
// every tick, yet after its first index it allocates nothing, because its cell table is sized for
// the most cells the body count allows, not for the ground covered so far.
TEST(SnapshotBuilderAllocation, ASpreadingCrowdAllocatesNothingAfterTheFirstIndex) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> pos(-5.0, 5.0);
  std::vector<std::uint32_t> id;
  std::vector<double> x, y, z;
  std::vector<float> yaw;
  for (std::uint32_t i = 0; i < 3000; ++i) {
    id.push_back(ObjectId::make(i, 0).value);
    x.push_back(pos(rng));
    y.push_back(pos(rng));
    z.push_back(0.9);
    yaw.push_back(0.0f);
  }
  SnapshotBuilder sb(InterestConfig{});
  sb.add_client(1);
  sb.index(BodyView{id, x, y, z, yaw}, 1);

  g_allocations = 0;
  g_counting = true;
  for (std::uint64_t t = 2; t <= 80; ++t) {
    for (std::size_t i = 0; i < id.size(); ++i) {  // 10 m across to about 470 m across
      x[i] *= 1.05;
      y[i] *= 1.05;
    }
    sb.index(BodyView{id, x, y, z, yaw}, t);
  }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0u);
}

// Match::save_checkpoint into a warm buffer (the server writes one every ~2 s on the tick
// thread): no allocation at all.
TEST(MatchCheckpointAlloc, SaveDoesNotAllocateWhenWarm) {
  Match m(test::two_armies(40), test::small_config(), "alloc");
  Outbox out;
  m.inputs().push(test::join_request(1, "a"));
  m.inputs().push(test::join_request(2, "b"));
  for (int t = 0; t < 40; ++t) m.tick(out);
  std::vector<std::uint8_t> bytes;
  m.save_checkpoint(bytes);
  g_allocations = 0;
  g_counting = true;
  for (int i = 0; i < 5; ++i) m.save_checkpoint(bytes);
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0u);
  EXPECT_GT(bytes.size(), 1000u);
}

}  // namespace
}  // namespace throng::match
