// "No allocation inside a tick after warm-up", checked by counting every operator new in this test
// binary while a settled crowd with scenery, morale and camera parameters ticks on.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <vector>

#include "world/world_fixtures.h"

#include "support/counting_new.h"  // counts operator new while g_counting is set

namespace throng {
namespace {

using namespace throng::test;

TEST(WorldNoAllocation, SettledCrowdTicksWithoutAllocating) {
  params::Term weight;
  weight.input = params::TermInput::weight_kg;
  weight.scale = 100.0;
  params::Term camera;
  camera.input = params::TermInput::camera_distance_m;
  camera.scale = 50.0;
  params::Term speed;
  speed.input = params::TermInput::speed_mps;
  speed.scale = 2.0;
  WorldSettings s;
  s.iterations = 8;
  params::ParamTable table = test_table();
  params::ObjectParams grouped = archetype_with(80.0);
  grouped.group_id = 1;
  table.set_archetype("grouped", grouped);
  table.groups().set(1, params::Group{});
  World w(s, table, params::PushPolicy(params::PushMode::ratio, {weight, camera, speed}, {}));
  w.add_fixed_box({0.0, 0.0, 1.0}, {0.3, 8.0, 1.0}, 0.0);
  w.add_fixed_box({6.0, 6.0, 1.0}, {1.0, 1.0, 1.0}, 0.0, "bush");
  const Vec3 cams[] = {{0.0, 0.0, 10.0}, {20.0, 0.0, 10.0}};
  w.set_cameras(cams);
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 40; ++j) add_sphere(w, -12.0 + 0.65 * i, -12.0 + 0.65 * j, 0.35, (i + j) % 3 ? "infantry" : "grouped");
  }
  for (std::size_t k = 0; k < w.body_count(); ++k) w.set_desired_velocity(w.id_at(k), {0.3, 0.0, 0.0});
  // Warm-up: scratch arrays reach their size. The crowd walks into the wall and its pile (and so
  // its pair count) keeps growing for a long while; the arrays grow geometrically, and after 120
  // ticks one still grew to a new high-water size within the next 64 (200-400: the same; from
  // ~500 on none does).
  for (int t = 0; t < 600; ++t) w.step();
  // The counter itself works: a vector allocated while counting is seen.
  g_counting = true;
  { std::vector<int> probe(16); EXPECT_EQ(probe.size(), 16u); }
  g_counting = false;
  ASSERT_GE(g_allocations.load(), 1u);
  g_allocations = 0;
  g_counting = true;
  for (int t = 0; t < 64; ++t) w.step();  // covers reorders (every 16) and morale periods (15)
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0u);
}

// The re-sort's buffers are sized on the first step after the crowd grew: the first re-sort and
// the settling of the parameter records after it allocate nothing (they ran on ordinary ticks,
// which the fresh memory made some of a run's slowest).
TEST(WorldNoAllocation, FirstReSortAndSettlingAllocateNothingAfterTheFirstStep) {
  WorldSettings s;
  s.iterations = 8;
  World w(s, test_table(), weight_policy(params::PushMode::ratio, 100.0));
  // A resting grid created in a scrambled order, so that the re-sort moves every body.
  constexpr int kSide = 30;
  for (int k = 0; k < kSide * kSide; ++k) {
    const int cell = (k * 7919) % (kSide * kSide);
    add_sphere(w, 0.8 * (cell % kSide), 0.8 * (cell / kSide), 0.35, k % 3 ? "infantry" : "heavy");
  }
  w.step();  // sizes the re-sort's buffers
  w.step();  // the list's first kept tick sizes its check
  std::uint32_t re_sorts = 0;
  g_allocations = 0;
  for (int t = 0; t < 18; ++t) {
    g_counting = true;
    w.step();
    g_counting = false;
    re_sorts += w.last_reorder().empty() ? 0 : 1;
  }
  EXPECT_EQ(re_sorts, 1u);
  EXPECT_EQ(g_allocations.load(), 0u);
}

// An open crowd (no scenery) keeps its pair list across ticks and searches a new one now and then
// (world_pair_list.cpp): neither allocates once the crowd has settled into its jam.
void open_crowd_ticks_without_allocating(int side, std::uint32_t threads) {
  WorldSettings s;
  s.iterations = 8;
  s.threads = threads;
  World w(s, test_table(), weight_policy(params::PushMode::ratio, 100.0));
  const double half = 0.33 * side;
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j) add_sphere(w, -half + 0.66 * i, -half + 0.66 * j, 0.35, (i + j) % 3 ? "infantry" : "heavy");
  }
  // Warm-up: the jam's pair count reaches its high-water size (after 200 ticks one array still grew
  // within the next 64 since held pairs start at the conflict share; from 260 on none does).
  for (int t = 0; t < 300; ++t) {
    steer_to_origin(w);
    w.step();
  }
  std::uint32_t kept = 0, searched = 0;
  g_allocations = 0;
  for (int t = 0; t < 64; ++t) {
    steer_to_origin(w);  // outside the counted step
    g_counting = true;
    const StepStats& st = w.step();
    g_counting = false;
    kept += st.pair_list_reused;
    // In a tick of its own, or begun ahead (how a settled jam replaces its lists: then every search
    // in the window is one begun ahead and finished by the next step).
    searched += 1 - st.pair_list_reused + st.pair_list_searched_ahead;
  }
  EXPECT_EQ(g_allocations.load(), 0u);
  EXPECT_GT(kept, 0u);
  EXPECT_GT(searched, 0u);
}

TEST(WorldNoAllocation, OpenCrowdWithAKeptPairListTicksWithoutAllocating) { open_crowd_ticks_without_allocating(40, 1); }

// The same on two threads, with enough bodies for several blocks a phase (pair_schedule.h): the
// pool hands out work without allocating, and its threads allocate nothing either.
TEST(WorldNoAllocation, TwoThreadsTickWithoutAllocating) { open_crowd_ticks_without_allocating(110, 2); }

}  // namespace
}  // namespace throng
