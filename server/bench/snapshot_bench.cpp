// Micro benchmarks of the snapshots phase (throng::match::SnapshotBuilder): one index() of the
// tick's bodies, then one build() per client, as match_snapshots.cpp does. A crowd of 6,000 bodies
// at about 1,000 per interest circle (30 m), walking at up to 1.5 m/s, 50 clients whose cameras
// move at 4 m/s, default budget (about 106 poses per snapshot).
//
//   throng-microbench --benchmark_filter=Snapshot
//
// BM_SnapshotBuild reports the time per build() (items = builds) in steady state; the positions
// are precomputed (a walk there and back, so the motion stays continuous while the benchmark
// repeats it) so that only the builder is timed.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <thread>
#include <vector>

#include "throng/core/object_id.h"
#include "throng/match/snapshot_builder.h"
#include "throng/protocol/messages.h"

namespace {

using namespace throng;
using namespace throng::match;

constexpr double kPi = 3.14159265358979323846;

struct Scene {
  static constexpr int kFrames = 120;  // forward, then the same frames backwards
  std::uint32_t clients = 0;
  std::vector<std::uint32_t> id;
  std::vector<std::vector<double>> x, y, cx, cy;  // [frame][body or client]
  std::vector<double> z;
  std::vector<std::vector<float>> yaw;
  std::vector<protocol::Snapshot> out;

  Scene(std::uint32_t bodies, std::uint32_t n_clients, double per_view) : clients(n_clients) {
    const double side = std::sqrt(bodies * kPi * 30.0 * 30.0 / per_view);
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> pos(0.0, side), ang(-kPi, kPi), speed(0.0, 1.5);
    std::vector<double> px(bodies), py(bodies), h(bodies), v(bodies);
    for (std::uint32_t i = 0; i < bodies; ++i) {
      id.push_back(ObjectId::make(i, 0).value);
      px[i] = pos(rng);
      py[i] = pos(rng);
      h[i] = ang(rng);
      v[i] = speed(rng);
    }
    std::vector<double> qx(clients), qy(clients), qh(clients);
    for (std::uint32_t c = 0; c < clients; ++c) {
      qx[c] = side * 0.25 + 0.5 * pos(rng);
      qy[c] = side * 0.25 + 0.5 * pos(rng);
      qh[c] = ang(rng);
    }
    z.assign(bodies, 0.9);
    const double dt = 1.0 / 30.0;
    for (int f = 0; f < kFrames; ++f) {
      for (std::uint32_t i = 0; i < bodies; ++i) {
        if ((f + static_cast<int>(i)) % 60 == 0) h[i] = ang(rng);
        px[i] += v[i] * dt * std::cos(h[i]);
        py[i] += v[i] * dt * std::sin(h[i]);
      }
      for (std::uint32_t c = 0; c < clients; ++c) {
        if ((f + static_cast<int>(c)) % 90 == 0) qh[c] = ang(rng);
        qx[c] += 4.0 * dt * std::cos(qh[c]);
        qy[c] += 4.0 * dt * std::sin(qh[c]);
      }
      x.push_back(px);
      y.push_back(py);
      cx.push_back(qx);
      cy.push_back(qy);
      std::vector<float> yw(bodies);
      for (std::uint32_t i = 0; i < bodies; ++i) yw[i] = static_cast<float>(h[i]);
      yaw.push_back(std::move(yw));
    }
    out.resize(clients);
  }
  int frame(std::uint64_t tick) const {  // 0 .. kFrames - 1 .. 0 ..
    const auto p = static_cast<int>(tick % (2 * kFrames - 2));
    return p < kFrames ? p : 2 * kFrames - 2 - p;
  }
  BodyView bodies(int f) const { return BodyView{id, x[f], y[f], z, yaw[f]}; }
};

// One tick: index + a build for every client (the phase match_snapshots.cpp runs).
void BM_SnapshotTick(benchmark::State& state) {
  Scene s(static_cast<std::uint32_t>(state.range(0)), static_cast<std::uint32_t>(state.range(1)), 1000.0);
  SnapshotBuilder sb(InterestConfig{});
  for (std::uint32_t c = 1; c <= s.clients; ++c) sb.add_client(c);
  std::uint64_t tick = 0;
  std::uint64_t in_view = 0, builds = 0;
  auto run = [&] {
    const int f = s.frame(++tick);
    sb.index(s.bodies(f), tick);
    for (std::uint32_t c = 0; c < s.clients; ++c) {
      const BuildStats& st = sb.build(c + 1, s.cx[f][c], s.cy[f][c], s.out[c]);
      in_view += st.in_view;
      ++builds;
    }
  };
  for (int i = 0; i < 60; ++i) run();  // warm-up: every client knows its view
  in_view = builds = 0;
  for (auto _ : state) run();
  state.SetItemsProcessed(static_cast<std::int64_t>(builds));
  state.counters["in_view"] = benchmark::Counter(builds ? static_cast<double>(in_view) / builds : 0.0);
}
BENCHMARK(BM_SnapshotTick)->Args({6000, 50})->Args({15000, 50})->Unit(benchmark::kMillisecond);

// The builds alone (index() once per 50 builds is not timed).
void BM_SnapshotBuild(benchmark::State& state) {
  Scene s(6000, 50, 1000.0);
  SnapshotBuilder sb(InterestConfig{});
  for (std::uint32_t c = 1; c <= s.clients; ++c) sb.add_client(c);
  SnapshotBuilder::Scratch scratch;
  std::uint64_t tick = 0;
  auto tick_all = [&] {
    const int f = s.frame(++tick);
    sb.index(s.bodies(f), tick);
    for (std::uint32_t c = 0; c < s.clients; ++c) sb.build(c + 1, s.cx[f][c], s.cy[f][c], s.out[c], scratch);
  };
  for (int i = 0; i < 60; ++i) tick_all();
  std::uint32_t c = 0;
  int f = s.frame(tick);
  for (auto _ : state) {
    if (c == s.clients) {
      state.PauseTiming();
      f = s.frame(++tick);
      sb.index(s.bodies(f), tick);
      c = 0;
      state.ResumeTiming();
    }
    benchmark::DoNotOptimize(sb.build(c + 1, s.cx[f][c], s.cy[f][c], s.out[c], scratch));
    ++c;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SnapshotBuild)->Unit(benchmark::kMicrosecond);

void BM_SnapshotIndex(benchmark::State& state) {
  Scene s(static_cast<std::uint32_t>(state.range(0)), 1, 1000.0);
  SnapshotBuilder sb(InterestConfig{});
  std::uint64_t tick = 0;
  for (auto _ : state) {
    ++tick;
    sb.index(s.bodies(s.frame(tick)), tick);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_SnapshotIndex)->Arg(6000)->Arg(15000)->Unit(benchmark::kMicrosecond);

// The tick's builds split over threads, one Scratch each (how the server may parallelise the
// phase): wall time per tick.
void BM_SnapshotTickThreads(benchmark::State& state) {
  Scene s(6000, 50, 1000.0);
  const auto n_threads = static_cast<std::uint32_t>(state.range(0));
  SnapshotBuilder sb(InterestConfig{});
  for (std::uint32_t c = 1; c <= s.clients; ++c) sb.add_client(c);
  std::vector<SnapshotBuilder::Scratch> scratch(n_threads);
  std::uint64_t tick = 0;
  auto run = [&] {
    const int f = s.frame(++tick);
    sb.index(s.bodies(f), tick);
    std::vector<std::thread> threads;
    for (std::uint32_t t = 1; t < n_threads; ++t)
      threads.emplace_back([&, t] {
        for (std::uint32_t c = t; c < s.clients; c += n_threads)
          sb.build(c + 1, s.cx[f][c], s.cy[f][c], s.out[c], scratch[t]);
      });
    for (std::uint32_t c = 0; c < s.clients; c += n_threads)
      sb.build(c + 1, s.cx[f][c], s.cy[f][c], s.out[c], scratch[0]);
    for (auto& th : threads) th.join();
  };
  for (int i = 0; i < 60; ++i) run();
  for (auto _ : state) run();
  state.SetItemsProcessed(state.iterations() * s.clients);
}
BENCHMARK(BM_SnapshotTickThreads)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
