// render(): text exposition format 0.0.4 as a Prometheus server reads it. The text is parsed, so
// the tests hold whatever the serializer's line order or float spelling; only what a scraper sees
// (names, HELP, TYPE, labels, values) is asserted.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>

#include "exposition_parser.h"
#include "throng/admin/metrics.h"

namespace throng::admin {
namespace {

using test::parse_exposition;
using test::series;

TEST(MetricsRender, EmptyRegistryRendersNothing) {
  MetricsRegistry reg;
  EXPECT_EQ(reg.render(), "");
}

TEST(MetricsRender, SmallRegistry) {
  MetricsRegistry reg;
  reg.counter("throng_ticks_total", "Simulation ticks run.").inc(3);
  Counter& nan = reg.counter("throng_commands_rejected_total", "Commands rejected, by reason.", {{"reason", "nan"}});
  Counter& speed = reg.counter("throng_commands_rejected_total", "Commands rejected, by reason.", {{"reason", "speed"}});
  nan.inc(2);
  speed.inc();
  reg.gauge("throng_clients", "Connected clients.").set(1.5);
  // Milliseconds with binary-exact values, so the sum is exact too.
  Histogram& tick = reg.histogram("throng_tick_ms", "Tick duration in milliseconds.", {1.0, 5.0, 16.0});
  tick.observe(0.5);
  tick.observe(1.0);  // le is inclusive: counts in the 1 bucket
  tick.observe(4.0);
  tick.observe(100.0);  // only in +Inf

  const auto e = parse_exposition(reg.render());
  EXPECT_EQ(e.families.size(), 4u);
  EXPECT_EQ(e.help.at("throng_ticks_total"), "Simulation ticks run.");
  EXPECT_EQ(e.help.at("throng_commands_rejected_total"), "Commands rejected, by reason.");
  EXPECT_EQ(e.help.at("throng_clients"), "Connected clients.");
  EXPECT_EQ(e.help.at("throng_tick_ms"), "Tick duration in milliseconds.");
  EXPECT_EQ(e.type.at("throng_ticks_total"), "counter");  // the name as given: no second _total
  EXPECT_EQ(e.type.at("throng_commands_rejected_total"), "counter");
  EXPECT_EQ(e.type.at("throng_clients"), "gauge");
  EXPECT_EQ(e.type.at("throng_tick_ms"), "histogram");

  EXPECT_EQ(e.samples.size(), 10u) << "no sample more than these";
  EXPECT_EQ(e.value("throng_ticks_total"), 3);
  EXPECT_EQ(e.value(series("throng_commands_rejected_total", {{"reason", "nan"}})), 2);
  EXPECT_EQ(e.value(series("throng_commands_rejected_total", {{"reason", "speed"}})), 1);
  EXPECT_EQ(e.value("throng_clients"), 1.5);
  EXPECT_EQ(e.value(series("throng_tick_ms_bucket", {{"le", "1"}})), 2);
  EXPECT_EQ(e.value(series("throng_tick_ms_bucket", {{"le", "5"}})), 3);
  EXPECT_EQ(e.value(series("throng_tick_ms_bucket", {{"le", "16"}})), 3);
  EXPECT_EQ(e.value(series("throng_tick_ms_bucket", {{"le", "+Inf"}})), 4);
  EXPECT_EQ(e.value("throng_tick_ms_sum"), 105.5);
  EXPECT_EQ(e.value("throng_tick_ms_count"), 4);
}

TEST(MetricsRender, LabelledHistogramSeriesKeepTheirLabelsOnEverySample) {
  MetricsRegistry reg;
  Histogram& solve = reg.histogram("throng_phase_seconds", "Phase duration.", {0.25, 0.5}, {{"phase", "solve"}});
  reg.histogram("throng_phase_seconds", "Phase duration.", {0.25, 0.5}, {{"phase", "move"}});
  solve.observe(0.375);
  const auto e = parse_exposition(reg.render());
  EXPECT_EQ(e.samples.size(), 10u);
  EXPECT_EQ(e.value(series("throng_phase_seconds_bucket", {{"phase", "solve"}, {"le", "0.25"}})), 0);
  EXPECT_EQ(e.value(series("throng_phase_seconds_bucket", {{"phase", "solve"}, {"le", "0.5"}})), 1);
  EXPECT_EQ(e.value(series("throng_phase_seconds_bucket", {{"phase", "solve"}, {"le", "+Inf"}})), 1);
  EXPECT_EQ(e.value(series("throng_phase_seconds_sum", {{"phase", "solve"}})), 0.375);
  EXPECT_EQ(e.value(series("throng_phase_seconds_count", {{"phase", "solve"}})), 1);
  EXPECT_EQ(e.value(series("throng_phase_seconds_bucket", {{"phase", "move"}, {"le", "+Inf"}})), 0);
  EXPECT_EQ(e.value(series("throng_phase_seconds_sum", {{"phase", "move"}})), 0);
  EXPECT_EQ(e.value(series("throng_phase_seconds_count", {{"phase", "move"}})), 0);
}

TEST(MetricsRender, OrderIsByNameThenLabelsWhateverTheRegistrationOrder) {
  MetricsRegistry reg;
  reg.gauge("throng_zeta", "z");
  reg.counter("throng_beta_total", "b", {{"k", "2"}});
  reg.counter("throng_beta_total", "b", {{"k", "1"}});
  reg.histogram("throng_alpha", "a", {1.0});
  EXPECT_THROW(reg.gauge("throng_zeta", "z"), std::invalid_argument);  // must not add anything
  const std::string text = reg.render();
  const auto e = parse_exposition(text);
  EXPECT_EQ(e.families, (std::vector<std::string>{"throng_alpha", "throng_beta_total", "throng_zeta"}));
  EXPECT_LT(text.find("throng_beta_total{k=\"1\"}"), text.find("throng_beta_total{k=\"2\"}"));
  EXPECT_EQ(reg.render(), text) << "two scrapes of unchanged metrics differ";
}

TEST(MetricsRender, EscapesLabelValuesAndKeepsHelpQuotes) {
  MetricsRegistry reg;
  reg.counter("throng_escape_total", "Help \"quotes\" stay.", {{"path", "C:\\dir\n\"x\""}}).inc();
  const std::string text = reg.render();
  const auto e = parse_exposition(text);
  EXPECT_EQ(e.help.at("throng_escape_total"), "Help \"quotes\" stay.");
  EXPECT_EQ(e.value(series("throng_escape_total", {{"path", "C:\\dir\n\"x\""}})), 1) << text;
}

TEST(MetricsRender, LabelsRenderSortedByName) {
  MetricsRegistry reg;
  reg.counter("throng_bytes_total", "Bytes.", {{"topic", "snapshot"}, {"dir", "out"}}).inc(7);
  EXPECT_NE(reg.render().find("\nthrong_bytes_total{dir=\"out\",topic=\"snapshot\"} 7\n"), std::string::npos)
      << reg.render();
}

std::string gauge_text(double v) {
  MetricsRegistry reg;
  reg.gauge("throng_g", "g").set(v);
  const std::string text = reg.render();
  const std::string prefix = "\nthrong_g ";  // the sample line, not the HELP line
  const auto at = text.find(prefix);
  return text.substr(at + prefix.size(), text.size() - at - prefix.size() - 1);
}

TEST(MetricsRender, DoublesReadWellAndKeepSixteenDigits) {
  // Everyday magnitudes read plainly; far ones in exponent notation.
  EXPECT_EQ(gauge_text(0.1), "0.1");
  EXPECT_EQ(gauge_text(-2.0), "-2");
  EXPECT_EQ(gauge_text(0.0005), "0.0005");
  EXPECT_EQ(gauge_text(123456789.0), "123456789");
  EXPECT_EQ(gauge_text(0.0), "0");
  EXPECT_EQ(std::strtod(gauge_text(1e21).c_str(), nullptr), 1e21);
  EXPECT_EQ(std::strtod(gauge_text(1e-5).c_str(), nullptr), 1e-5);
  EXPECT_EQ(gauge_text(std::numeric_limits<double>::infinity()), "+Inf");
  EXPECT_EQ(gauge_text(-std::numeric_limits<double>::infinity()), "-Inf");
  EXPECT_TRUE(std::isnan(std::strtod(gauge_text(std::nan("")).c_str(), nullptr)));  // Go's parser takes any case

  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> exponent(-300.0, 300.0);
  for (int i = 0; i < 2000; ++i) {
    const double v = std::pow(10.0, exponent(rng)) * (i % 2 ? 1.0 : -1.0);
    const std::string s = gauge_text(v);
    EXPECT_NEAR(std::strtod(s.c_str(), nullptr), v, std::fabs(v) * 1e-15) << s;
  }
}

TEST(MetricsRender, CountersRenderWholeNumbersInFull) {
  MetricsRegistry reg;
  Counter& bytes = reg.counter("throng_bytes_total", "Bytes.");
  bytes.inc(123'456'789'012ull);  // a byte count of a long match: no exponent notation
  Counter& big = reg.counter("throng_big_total", "Big.");
  big.inc(std::uint64_t{1} << 53);  // the largest a double counts exactly
  big.inc(0);
  const std::string text = reg.render();
  EXPECT_NE(text.find("\nthrong_bytes_total 123456789012\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\nthrong_big_total 9007199254740992\n"), std::string::npos) << text;
  EXPECT_EQ(big.value(), std::uint64_t{1} << 53);
}

TEST(MetricsRender, HistogramNanGoesToInfBucketOnly) {
  MetricsRegistry reg;
  Histogram& h = reg.histogram("throng_h", "h", {1.0});
  h.observe(std::nan(""));
  const auto e = parse_exposition(reg.render());
  EXPECT_EQ(e.value(series("throng_h_bucket", {{"le", "1"}})), 0);
  EXPECT_EQ(e.value(series("throng_h_bucket", {{"le", "+Inf"}})), 1);
  EXPECT_EQ(e.value("throng_h_count"), 1);
}

TEST(MetricsRender, RenderToAppends) {
  MetricsRegistry reg;
  reg.counter("throng_c_total", "c");
  std::string out = "prefix\n";
  reg.render_to(out);
  EXPECT_EQ(out, "prefix\n" + reg.render());
  EXPECT_NE(out.find("throng_c_total 0\n"), std::string::npos);
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
