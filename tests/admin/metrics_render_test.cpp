// render(): the exact text exposition format 0.0.4 a Prometheus server will parse.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>

#include "throng/admin/metrics.h"

namespace throng::admin {
namespace {

TEST(MetricsRender, EmptyRegistryRendersNothing) {
  MetricsRegistry reg;
  EXPECT_EQ(reg.render(), "");
}

TEST(MetricsRender, SmallRegistryExactText) {
  MetricsRegistry reg;
  reg.counter("throng_ticks_total", "Simulation ticks run.").inc(3);
  Counter& nan = reg.counter("throng_commands_rejected_total", "Commands rejected, by reason.", {{"reason", "nan"}});
  Counter& speed = reg.counter("throng_commands_rejected_total", "Commands rejected, by reason.", {{"reason", "speed"}});
  nan.inc(2);
  speed.inc();
  reg.gauge("throng_clients", "Connected clients.").set(1.5);
  // Milliseconds with binary-exact values, so the sum's text is exact too.
  Histogram& tick = reg.histogram("throng_tick_ms", "Tick duration in milliseconds.", {1.0, 5.0, 16.0});
  tick.observe(0.5);
  tick.observe(1.0);  // le is inclusive: counts in the 1 bucket
  tick.observe(4.0);
  tick.observe(100.0);  // only in +Inf

  EXPECT_EQ(reg.render(),
            "# HELP throng_ticks_total Simulation ticks run.\n"
            "# TYPE throng_ticks_total counter\n"
            "throng_ticks_total 3\n"
            "# HELP throng_commands_rejected_total Commands rejected, by reason.\n"
            "# TYPE throng_commands_rejected_total counter\n"
            "throng_commands_rejected_total{reason=\"nan\"} 2\n"
            "throng_commands_rejected_total{reason=\"speed\"} 1\n"
            "# HELP throng_clients Connected clients.\n"
            "# TYPE throng_clients gauge\n"
            "throng_clients 1.5\n"
            "# HELP throng_tick_ms Tick duration in milliseconds.\n"
            "# TYPE throng_tick_ms histogram\n"
            "throng_tick_ms_bucket{le=\"1\"} 2\n"
            "throng_tick_ms_bucket{le=\"5\"} 3\n"
            "throng_tick_ms_bucket{le=\"16\"} 3\n"
            "throng_tick_ms_bucket{le=\"+Inf\"} 4\n"
            "throng_tick_ms_sum 105.5\n"
            "throng_tick_ms_count 4\n");
}

TEST(MetricsRender, LabelledHistogramPutsLeLast) {
  MetricsRegistry reg;
  Histogram& solve = reg.histogram("throng_phase_seconds", "Phase duration.", {0.25, 0.5}, {{"phase", "solve"}});
  reg.histogram("throng_phase_seconds", "Phase duration.", {0.25, 0.5}, {{"phase", "move"}});
  solve.observe(0.375);
  EXPECT_EQ(reg.render(),
            "# HELP throng_phase_seconds Phase duration.\n"
            "# TYPE throng_phase_seconds histogram\n"
            "throng_phase_seconds_bucket{phase=\"solve\",le=\"0.25\"} 0\n"
            "throng_phase_seconds_bucket{phase=\"solve\",le=\"0.5\"} 1\n"
            "throng_phase_seconds_bucket{phase=\"solve\",le=\"+Inf\"} 1\n"
            "throng_phase_seconds_sum{phase=\"solve\"} 0.375\n"
            "throng_phase_seconds_count{phase=\"solve\"} 1\n"
            "throng_phase_seconds_bucket{phase=\"move\",le=\"0.25\"} 0\n"
            "throng_phase_seconds_bucket{phase=\"move\",le=\"0.5\"} 0\n"
            "throng_phase_seconds_bucket{phase=\"move\",le=\"+Inf\"} 0\n"
            "throng_phase_seconds_sum{phase=\"move\"} 0\n"
            "throng_phase_seconds_count{phase=\"move\"} 0\n");
}

TEST(MetricsRender, OrderIsRegistrationOrderNotAlphabetical) {
  MetricsRegistry reg;
  reg.gauge("throng_zeta", "z");
  reg.gauge("throng_alpha", "a");
  EXPECT_THROW(reg.gauge("throng_zeta", "z"), std::invalid_argument);  // must not reorder anything
  const std::string text = reg.render();
  EXPECT_LT(text.find("throng_zeta"), text.find("throng_alpha"));
}

TEST(MetricsRender, EscapesLabelValuesAndHelp) {
  MetricsRegistry reg;
  reg.counter("throng_escape_total", "Line one\nback\\slash \"quotes\" stay.", {{"path", "C:\\dir\n\"x\""}}).inc();
  EXPECT_EQ(reg.render(),
            "# HELP throng_escape_total Line one\\nback\\\\slash \"quotes\" stay.\n"
            "# TYPE throng_escape_total counter\n"
            "throng_escape_total{path=\"C:\\\\dir\\n\\\"x\\\"\"} 1\n");
}

TEST(MetricsRender, MultipleLabelsKeepGivenOrder) {
  MetricsRegistry reg;
  reg.counter("throng_bytes_total", "Bytes.", {{"dir", "out"}, {"topic", "snapshot"}}).inc(7);
  EXPECT_NE(reg.render().find("throng_bytes_total{dir=\"out\",topic=\"snapshot\"} 7\n"), std::string::npos);
}

std::string gauge_text(double v) {
  MetricsRegistry reg;
  reg.gauge("throng_g", "g").set(v);
  const std::string text = reg.render();
  const std::string prefix = "\nthrong_g ";  // the sample line, not the HELP line
  const auto at = text.find(prefix);
  return text.substr(at + prefix.size(), text.size() - at - prefix.size() - 1);
}

TEST(MetricsRender, DoublesRoundTripReadablyAndSpecialValuesUsePrometheusSpelling) {
  EXPECT_EQ(gauge_text(0.1), "0.1");
  EXPECT_EQ(gauge_text(-2.0), "-2");
  EXPECT_EQ(gauge_text(0.0005), "0.0005");
  EXPECT_EQ(gauge_text(123456789.0), "123456789");
  EXPECT_EQ(gauge_text(0.0), "0");
  EXPECT_EQ(gauge_text(1e21), "1e+21");
  EXPECT_EQ(gauge_text(1e-5), "1e-05");
  EXPECT_EQ(gauge_text(1e300), "1e+300");
  EXPECT_EQ(gauge_text(std::numeric_limits<double>::infinity()), "+Inf");
  EXPECT_EQ(gauge_text(-std::numeric_limits<double>::infinity()), "-Inf");
  EXPECT_EQ(gauge_text(std::nan("")), "NaN");

  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> exponent(-300.0, 300.0);
  for (int i = 0; i < 2000; ++i) {
    const double v = std::pow(10.0, exponent(rng)) * (i % 2 ? 1.0 : -1.0);  // both notations
    const std::string s = gauge_text(v);
    EXPECT_EQ(std::strtod(s.c_str(), nullptr), v) << s;
  }
}

TEST(MetricsRender, HistogramNanGoesToInfBucketOnly) {
  MetricsRegistry reg;
  Histogram& h = reg.histogram("throng_h", "h", {1.0});
  h.observe(std::nan(""));
  const std::string text = reg.render();
  EXPECT_NE(text.find("throng_h_bucket{le=\"1\"} 0\n"), std::string::npos) << text;
  EXPECT_NE(text.find("throng_h_bucket{le=\"+Inf\"} 1\n"), std::string::npos) << text;
}

TEST(MetricsRender, RenderToAppends) {
  MetricsRegistry reg;
  reg.counter("throng_c_total", "c");
  std::string out = "prefix\n";
  reg.render_to(out);
  EXPECT_EQ(out, "prefix\n" + reg.render());
}

TEST(MetricsBuckets, LinearAndExponentialHelpers) {
  EXPECT_EQ(linear_buckets(1.0, 2.0, 3), (std::vector<double>{1.0, 3.0, 5.0}));
  EXPECT_EQ(exponential_buckets(1.0, 2.0, 4), (std::vector<double>{1.0, 2.0, 4.0, 8.0}));
  EXPECT_THROW(linear_buckets(0.0, 0.0, 3), std::invalid_argument);
  EXPECT_THROW(exponential_buckets(0.0, 2.0, 3), std::invalid_argument);
  EXPECT_THROW(exponential_buckets(1.0, 1.0, 3), std::invalid_argument);
}

}  // namespace
}  // namespace throng::admin
