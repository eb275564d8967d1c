// Micro benchmarks of the scene tools: what the bench itself costs next to the World it measures.
#include <benchmark/benchmark.h>

#include "throng/scene/build_scene.h"
#include "throng/scene/builtin_scenes.h"
#include "throng/scene/residual.h"
#include "throng/scene/scale.h"
#include "throng/scene/spawn.h"

namespace {

using namespace throng::scene;

BuiltScene crush(std::int64_t agents) { return build_scene(scale_scene(builtin_scene("crush"), std::uint64_t(agents))); }

// The residual metric must stay O(N): time per body should be flat across N.
void BM_ResidualCrushStart(benchmark::State& state) {
  BuiltScene b = crush(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(measure_residual(b.world));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_ResidualCrushStart)->RangeMultiplier(10)->Range(1'000, 100'000)->Unit(benchmark::kMillisecond);

// All bodies at one point: counted as one class, not N^2 / 2 pairs.
void BM_ResidualOneCell(benchmark::State& state) {
  BuiltScene b = build_scene(scale_scene(builtin_scene("one_cell"), std::uint64_t(state.range(0))));
  for (auto _ : state) benchmark::DoNotOptimize(measure_residual(b.world));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_ResidualOneCell)->RangeMultiplier(10)->Range(1'000, 100'000)->Unit(benchmark::kMillisecond);

void BM_SpawnDisk(benchmark::State& state) {
  SpawnShape d;
  d.kind = SpawnAreaKind::disk;
  d.radius_m = 50.0;
  for (auto _ : state) benchmark::DoNotOptimize(spawn_positions(d, std::uint32_t(state.range(0)), 1));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_SpawnDisk)->Arg(20'000);

void BM_DriverApply(benchmark::State& state) {
  BuiltScene b = crush(state.range(0));
  for (auto _ : state) b.driver.apply(b.world);
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_DriverApply)->Arg(20'000)->Unit(benchmark::kMicrosecond);

// One crush tick (driver + World::step) after 60 ticks of settling.
void BM_CrushTick(benchmark::State& state) {
  BuiltScene b = crush(state.range(0));
  for (int t = 0; t < 60; ++t) step_scene(b);
  for (auto _ : state) benchmark::DoNotOptimize(step_scene(b).total_us);
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_CrushTick)->Arg(2'000)->Arg(20'000)->Unit(benchmark::kMillisecond);

}  // namespace
