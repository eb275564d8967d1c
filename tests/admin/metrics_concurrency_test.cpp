// The tick thread updates while the admin thread renders: updates from several threads must all
// land, and rendering alongside them must neither crash nor show an inconsistent histogram.
#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include "throng/admin/metrics.h"

namespace throng::admin {
namespace {

TEST(MetricsConcurrency, IncrementsFromSeveralThreadsSumExactly) {
  MetricsRegistry reg;
  Counter& counter = reg.counter("throng_events_total", "Events.");
  Counter& labelled = reg.counter("throng_rejected_total", "Rejected.", {{"reason", "nan"}});
  Gauge& gauge = reg.gauge("throng_level", "Level.");
  Histogram& hist = reg.histogram("throng_size", "Size.", {1.0, 2.0});

  constexpr int threads = 4;
  constexpr int per_thread = 50'000;
  std::atomic<bool> done{false};
  // Render concurrently the whole time: exercises the read side against the writers.
  std::thread renderer([&] {
    while (!done.load()) {
      const std::string text = reg.render();
      ASSERT_NE(text.find("throng_size_count"), std::string::npos);
    }
  });
  std::vector<std::thread> workers;
  for (int t = 0; t < threads; ++t) {
    workers.emplace_back([&, t] {
      for (int i = 0; i < per_thread; ++i) {
        counter.inc();
        labelled.inc(2);
        gauge.add(1.0);  // integers stay exact in a double far beyond this count
        hist.observe(static_cast<double>((i + t) % 3));  // 0, 1, 2 in turn: all <= 2
      }
    });
  }
  for (auto& w : workers) w.join();
  done = true;
  renderer.join();

  constexpr std::uint64_t total = std::uint64_t{threads} * per_thread;
  EXPECT_EQ(counter.value(), total);
  EXPECT_EQ(labelled.value(), 2 * total);
  EXPECT_EQ(gauge.value(), static_cast<double>(total));
  std::uint64_t observed = 0;
  for (std::size_t i = 0; i <= hist.bounds().size(); ++i) observed += hist.slot_count(i);
  EXPECT_EQ(observed, total);
  EXPECT_EQ(hist.slot_count(2), 0u);  // nothing above the last bound
  const std::string text = reg.render();
  EXPECT_NE(text.find("throng_size_count " + std::to_string(total) + "\n"), std::string::npos) << text;
  EXPECT_NE(text.find("throng_size_bucket{le=\"+Inf\"} " + std::to_string(total) + "\n"), std::string::npos);
}

TEST(MetricsConcurrency, RegistrationWhileRenderingIsSafe) {
  MetricsRegistry reg;
  std::atomic<bool> done{false};
  std::thread renderer([&] {
    while (!done.load()) (void)reg.render();
  });
  for (int i = 0; i < 500; ++i) {
    reg.counter("throng_dynamic_total", "Dynamic.", {{"id", std::to_string(i)}}).inc();
  }
  done = true;
  renderer.join();
  EXPECT_NE(reg.render().find("throng_dynamic_total{id=\"499\"} 1\n"), std::string::npos);
}

}  // namespace
}  // namespace throng::admin
