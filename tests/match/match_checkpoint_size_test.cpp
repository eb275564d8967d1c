// Size and speed of a checkpoint of the server's default match (built-in battle scaled to 6,000
// bodies, 30 Hz) with a few clients: printed for the record, asserted only loosely (no wall-time
// limits in tests; the figures are in the report). Save must be mostly memcpy. Times are this
// thread's CPU time (CLOCK_THREAD_CPUTIME_ID), so a loaded machine inflates them less than wall time.
#include <gtest/gtest.h>

#include <ctime>
#include <cstdio>
#include <vector>

#include "match_test_util.h"
#include "throng/match/match.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"
#include "throng/world/world.h"

namespace throng::match {
namespace {

double thread_us() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) * 1e-3;
}

TEST(MatchCheckpointSize, BattleAtSixThousandBodies) {
  MatchConfig config;  // the server's defaults
  Match m(scene::scale_scene(scene::builtin_scene("battle"), 6000), config, "size");
  Outbox out;
  for (std::uint64_t n = 1; n <= 8; ++n) m.inputs().push(test::join_request(n, "bot"));
  for (int t = 0; t < 60; ++t) m.tick(out);
  std::vector<std::uint8_t> bytes;
  m.save_checkpoint(bytes);  // warm the buffer
  constexpr int kSaves = 200;
  const auto t0 = thread_us();
  for (int i = 0; i < kSaves; ++i) m.save_checkpoint(bytes);
  const auto t1 = thread_us();
  std::vector<std::uint8_t> world_bytes;
  m.world().save_state(world_bytes);
  const auto tw0 = thread_us();
  for (int i = 0; i < kSaves; ++i) m.world().save_state(world_bytes);
  const auto tw1 = thread_us();
  const double world_us = (tw1 - tw0) / kSaves;
  std::printf("  of which world section: %zu bytes, save %.1f us\n", world_bytes.size(), world_us);
  Match fresh(scene::scale_scene(scene::builtin_scene("battle"), 6000), config, "fresh");
  constexpr int kRestores = 5;
  const auto t2 = thread_us();
  for (int i = 0; i < kRestores; ++i) fresh.restore_checkpoint(bytes);
  const auto t3 = thread_us();
  const double save_us = (t1 - t0) / kSaves;
  const double restore_us = (t3 - t2) / kRestores;
  std::printf("checkpoint: %zu bodies, %zu bytes (%.1f B/body), save %.1f us, restore %.1f us\n", m.world().body_count(),
              bytes.size(), static_cast<double>(bytes.size()) / static_cast<double>(m.world().body_count()), save_us,
              restore_us);
  RecordProperty("bytes", static_cast<int>(bytes.size()));
  RecordProperty("save_us", static_cast<int>(save_us));
  RecordProperty("restore_us", static_cast<int>(restore_us));
  EXPECT_EQ(fresh.state_hash(), m.state_hash());
  EXPECT_LT(bytes.size(), 6000u * 500u);  // a few hundred bytes per body, not kilobytes
}

}  // namespace
}  // namespace throng::match
