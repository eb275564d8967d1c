// Timing of a full-size match (disabled: run with --gtest_also_run_disabled_tests
// --gtest_filter='*Timing*' on a Release build). The battle scene scaled to 6,000 NPCs with 50
// clients sending a command every tick; prints the median / p95 / max of every tick phase while the
// armies march and once the lines press into each other.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <vector>

#include "match_test_util.h"
#include "throng/match/match.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/scale.h"

namespace throng::match {
namespace {

struct Series {
  const char* name;
  std::vector<double> v;
  void print() {
    std::sort(v.begin(), v.end());
    const auto at = [&](double q) { return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))]; };
    std::printf("%-10s median %8.1f us   p95 %8.1f us   max %8.1f us\n", name, at(0.5), at(0.95), v.back());
  }
};

TEST(MatchTiming, DISABLED_Battle6000With50Clients) {
  MatchConfig config;
  Match m(scene::scale_scene(scene::builtin_scene("battle"), 6000), config, "timing");
  Outbox out;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> clients;  // id, entity
  for (std::uint64_t n = 1; n <= 50; ++n) m.inputs().push(test::join_request(n, "bot"));
  m.tick(out);
  for (const auto& r : out.join_replies) clients.emplace_back(r.client_id, r.entity);
  ASSERT_EQ(clients.size(), 50u);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> unit(-0.7f, 0.7f);
  // Two windows: the armies marching (ticks 30..600) and the lines pressing (1200..1500).
  const int windows[2][2] = {{30, 600}, {1200, 1500}};
  const char* names[2] = {"marching", "engaged"};
  int t = 0;
  for (int w = 0; w < 2; ++w) {
    Series drain{"drain", {}}, apply{"apply", {}}, ai{"ai", {}}, step{"step", {}}, snaps{"snapshots", {}},
        total{"total", {}};
    std::uint64_t contacts = 0, poses = 0;
    for (; t < windows[w][1]; ++t) {
      for (auto [id, entity] : clients) {
        protocol::Command c = test::command(id, entity, static_cast<std::uint32_t>(t + 1), unit(rng), unit(rng));
        c.camera_x = 0.0f;
        m.inputs().push(std::move(c));
      }
      const TickReport& r = m.tick(out);
      if (t < windows[w][0]) continue;
      drain.v.push_back(r.drain_us);
      apply.v.push_back(r.apply_us);
      ai.v.push_back(r.ai_us);
      step.v.push_back(r.step_us);
      snaps.v.push_back(r.snapshots_us);
      total.v.push_back(r.total_us);
      contacts += r.push_events;
      poses += r.snapshot_poses;
    }
    const double n = static_cast<double>(windows[w][1] - windows[w][0]);
    std::printf("battle scaled to 6000 bodies, 50 clients, %s (ticks %d..%d at %u Hz)\n", names[w], windows[w][0],
                windows[w][1], config.tick_hz);
    for (Series* s : {&drain, &apply, &ai, &step, &snaps, &total}) s->print();
    std::printf("push events per tick %.0f, snapshot poses per tick %.0f\n", static_cast<double>(contacts) / n,
                static_cast<double>(poses) / n);
  }
}

}  // namespace
}  // namespace throng::match
