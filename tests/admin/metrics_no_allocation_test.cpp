// "Updates never allocate after registration", checked by counting every operator new in this
// test binary while counters, gauges and histograms are updated the way the tick thread does.
// Counting is off except inside the measured block, so the other suites in the binary are unaffected.
// The replaced operator new also serves libprometheus-cpp-core, so its allocations count too.
// prometheus-cpp's Histogram::Observe takes that histogram's mutex: acceptable; allocation is not.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <vector>

#include "throng/admin/metrics.h"

#include "support/counting_new.h"  // counts operator new while g_counting is set

namespace throng::admin {
namespace {

TEST(MetricsNoAllocation, UpdatesDoNotAllocate) {
  MetricsRegistry reg;
  Counter& counter = reg.counter("throng_ticks_total", "Ticks.");
  Counter& labelled = reg.counter("throng_rejected_total", "Rejected.", {{"reason", "nan"}});
  Gauge& gauge = reg.gauge("throng_clients", "Clients.");
  Histogram& hist = reg.histogram("throng_tick_seconds", "Tick.", exponential_buckets(0.0001, 2.0, 12));

  // The counter itself works: a vector allocated while counting is seen.
  g_allocations = 0;
  g_counting = true;
  { std::vector<int> probe(16); }
  g_counting = false;
  ASSERT_GE(g_allocations.load(), 1u);

  g_allocations = 0;
  g_counting = true;
  for (int i = 0; i < 10'000; ++i) {
    counter.inc();
    labelled.inc(3);
    gauge.set(static_cast<double>(i));
    gauge.add(0.5);
    hist.observe(0.00001 * i);
  }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0u);
  EXPECT_EQ(counter.value(), 10'000u);
}

}  // namespace
}  // namespace throng::admin
