// The path model: what it is asked to do is what it does, measured over many packets.
#include <gtest/gtest.h>

#include <cmath>

#include "throng/link/impairment.h"

namespace throng::link {
namespace {

using std::chrono::milliseconds;

// Packets every `spacing`, n of them; returns the decisions.
std::vector<Decision> run(Impairment& path, int n, Micros spacing, std::size_t bytes = 200) {
  std::vector<Decision> out;
  for (int i = 0; i < n; ++i) out.push_back(path.decide(spacing * i, bytes));
  return out;
}

// Four standard deviations of a binomial proportion: a test that fails by chance about once in
// 15,000 runs, and never for a fixed seed.
double tolerance(double p, int n) { return 4 * std::sqrt(p * (1 - p) / n); }

TEST(Impairment, RandomLossIsTheRateAskedFor) {
  for (const double p : {0.01, 0.03, 0.2}) {
    ImpairmentConfig c;
    c.loss = p;
    Impairment path(c, 7);
    const int n = 100'000;
    run(path, n, Micros(100));
    const double got = static_cast<double>(path.counters().lost_random) / n;
    EXPECT_NEAR(got, p, tolerance(p, n)) << "asked " << p;
    EXPECT_EQ(path.counters().delivered + path.counters().lost_random, static_cast<std::uint64_t>(n));
  }
}

TEST(Impairment, DelayAndJitterStayInTheirBandAndKeepOrder) {
  ImpairmentConfig c;
  c.delay = milliseconds(50);
  c.jitter = milliseconds(5);
  Impairment path(c, 11);
  const auto d = run(path, 20'000, Micros(1000));  // packets closer than 2 x jitter: order holds some back
  Micros last{0};
  double sum = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    ASSERT_EQ(d[i].fate, Fate::deliver);
    ASSERT_GE(d[i].release, last) << "packet " << i << " overtook the one before it";
    last = d[i].release;
    const Micros delay = d[i].release - Micros(1000) * static_cast<int>(i);
    ASSERT_GE(delay, milliseconds(45));
    ASSERT_LE(delay, milliseconds(55));
    sum += static_cast<double>(delay.count());
  }
  // Holding packets behind earlier ones raises the mean above 50 ms, by under the jitter.
  EXPECT_GT(sum / static_cast<double>(d.size()), 50'000);
  EXPECT_LT(sum / static_cast<double>(d.size()), 55'000);
  EXPECT_NEAR(path.delays().quantile_ms(0.5), 51.5, 2.0);
  EXPECT_EQ(path.counters().reordered, 0u);
}

TEST(Impairment, WidelySpacedPacketsShowTheJitterUniformly) {
  ImpairmentConfig c;
  c.delay = milliseconds(50);
  c.jitter = milliseconds(5);
  Impairment path(c, 12);
  run(path, 20'000, milliseconds(20));  // further apart than the jitter: none is held back
  EXPECT_NEAR(path.delays().mean_ms(), 50.0, 0.1);
  EXPECT_NEAR(path.delays().quantile_ms(0.5), 50.0, 0.2);
  EXPECT_NEAR(path.delays().quantile_ms(0.99), 54.9, 0.2);
  EXPECT_GE(path.delays().min_ms(), 45.0);
  EXPECT_LE(path.delays().max_ms(), 55.0);
}

TEST(Impairment, ReorderingLetsTheAskedShareOutOfOrder) {
  ImpairmentConfig c;
  c.delay = milliseconds(20);
  c.reorder = 0.05;
  Impairment path(c, 3);
  const int n = 50'000;
  const auto d = run(path, n, Micros(500));
  int overtaken = 0;
  for (int i = 1; i < n; ++i) overtaken += d[static_cast<std::size_t>(i)].release < d[static_cast<std::size_t>(i) - 1].release;
  EXPECT_NEAR(static_cast<double>(path.counters().reordered) / n, 0.05, tolerance(0.05, n));
  EXPECT_GT(overtaken, n / 40);  // most reordered packets are overtaken by the next one
}

TEST(Impairment, GilbertElliottBurstsHaveTheirMeanLengthAndRate) {
  ImpairmentConfig c;
  c.burst = {0.01, 0.25, 1.0, 0.0};  // stationary bad share 0.01 / 0.26, mean burst 4 packets
  Impairment path(c, 5);
  const int n = 400'000;
  run(path, n, Micros(100));
  const auto& k = path.counters();
  const double rate = static_cast<double>(k.lost_burst) / n;
  EXPECT_NEAR(rate, 0.01 / 0.26, 0.004);
  const double mean_burst = static_cast<double>(k.lost_burst) / static_cast<double>(k.bursts);
  EXPECT_NEAR(mean_burst, 4.0, 0.3);
  EXPECT_GE(k.longest_burst, 15u);  // geometric tails: random loss at this rate would give runs of 3-4
}

TEST(Impairment, TheBandwidthCapPacesPacketsAndDropsBeyondTheQueue) {
  ImpairmentConfig c;
  c.rate_bits_per_s = 1'000'000;  // 1000-byte packets: 8 ms each
  c.queue = milliseconds(40);
  Impairment path(c, 1);
  const auto d = run(path, 100, Micros(1000), 1000);  // 8 Mbit/s offered
  Micros prev{-1};
  int delivered = 0;
  for (const Decision& x : d) {
    if (x.fate != Fate::deliver) continue;
    ++delivered;
    if (prev.count() >= 0) {
      EXPECT_GE(x.release - prev, milliseconds(8));
    }
    prev = x.release;
  }
  EXPECT_GT(path.counters().lost_queue, 0u);
  // 100 ms of offered load at 1 Mbit/s plus a 40 ms buffer: about (100 + 40) / 8 packets.
  EXPECT_NEAR(delivered, 17, 2);
}

TEST(Impairment, TheSameSeedGivesTheSameFates) {
  ImpairmentConfig c;
  c.loss = 0.1;
  c.jitter = milliseconds(3);
  c.delay = milliseconds(10);
  c.reorder = 0.02;
  Impairment a(c, 99), b(c, 99), other(c, 100);
  const auto da = run(a, 5000, Micros(700)), db = run(b, 5000, Micros(700)), dc = run(other, 5000, Micros(700));
  bool differs = false;
  for (std::size_t i = 0; i < da.size(); ++i) {
    ASSERT_EQ(da[i].fate, db[i].fate);
    ASSERT_EQ(da[i].release, db[i].release);
    differs |= da[i].fate != dc[i].fate || da[i].release != dc[i].release;
  }
  EXPECT_TRUE(differs);
}

TEST(Impairment, CheckRefusesWhatCannotBeAPath) {
  ImpairmentConfig c;
  EXPECT_EQ(check(c), "");
  c.loss = std::nan("");
  EXPECT_NE(check(c), "");
  c.loss = 1.5;
  EXPECT_NE(check(c), "");
  c = {};
  c.delay = Micros(-1);
  EXPECT_NE(check(c), "");
  c = {};
  c.burst = {0.1, 0.0, 1.0, 0.0};  // a burst that never ends
  EXPECT_NE(check(c), "");
  c = {};
  c.reorder = -0.1;
  EXPECT_NE(check(c), "");
}

}  // namespace
}  // namespace throng::link
