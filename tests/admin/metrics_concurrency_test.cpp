// The tick thread updates while the admin thread renders: updates from several threads must all
// land, and every render alongside them must be valid text with a consistent histogram (buckets
// cumulative, the +Inf bucket equal to _count).
#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include "exposition_parser.h"
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
  // Render concurrently the whole time (at least once): exercises the read side against the writers.
  std::thread renderer([&] {
    for (bool first = true; first || !done.load(); first = false) {
      const auto e = test::parse_exposition(reg.render());
      const double le1 = e.value(test::series("throng_size_bucket", {{"le", "1"}}));
      const double le2 = e.value(test::series("throng_size_bucket", {{"le", "2"}}));
      const double inf = e.value(test::series("throng_size_bucket", {{"le", "+Inf"}}));
      EXPECT_LE(le1, le2);
      EXPECT_LE(le2, inf);
      EXPECT_EQ(inf, e.value("throng_size_count"));
      if (::testing::Test::HasFailure()) return;  // one report, not one per render
    }
  });
  std::vector<std::thread> workers;
  for (int t = 0; t < threads; ++t) {
    workers.emplace_back([&, t] {
      for (int i = 0; i < per_thread; ++i) {
        counter.inc();
        labelled.inc(2);
        gauge.add(1.0);  // integers stay exact in a double far beyond this count
        hist.observe(static_cast<double>((i + t) % 3));  // 0, 1, 2 in turn: all <= 2, one in three > 1
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
  std::uint64_t ones = 0, twos = 0;  // the observations of 1 and 2, counted as the workers made them
  for (int t = 0; t < threads; ++t) {
    for (int i = 0; i < per_thread; ++i) {
      ones += (i + t) % 3 == 1;
      twos += (i + t) % 3 == 2;
    }
  }
  const auto e = test::parse_exposition(reg.render());
  EXPECT_EQ(e.value("throng_events_total"), static_cast<double>(total));
  EXPECT_EQ(e.value(test::series("throng_rejected_total", {{"reason", "nan"}})), static_cast<double>(2 * total));
  EXPECT_EQ(e.value("throng_size_count"), static_cast<double>(total));
  EXPECT_EQ(e.value(test::series("throng_size_bucket", {{"le", "+Inf"}})), static_cast<double>(total));
  EXPECT_EQ(e.value(test::series("throng_size_bucket", {{"le", "2"}})), static_cast<double>(total));  // none above 2
  EXPECT_EQ(e.value(test::series("throng_size_bucket", {{"le", "1"}})), static_cast<double>(total - twos));
  EXPECT_EQ(e.value("throng_size_sum"), static_cast<double>(ones + 2 * twos));
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
  const auto e = test::parse_exposition(reg.render());
  EXPECT_EQ(e.samples.size(), 500u);
  EXPECT_EQ(e.value(test::series("throng_dynamic_total", {{"id", "499"}})), 1);
}

}  // namespace
}  // namespace throng::admin
