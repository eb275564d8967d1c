// Registration rejects everything that would make the exposition invalid or ambiguous.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include "exposition_parser.h"
#include "throng/admin/metrics.h"

namespace throng::admin {
namespace {

// Runs `f` and returns the std::invalid_argument message, or "" if nothing was thrown.
template <class F>
std::string rejection(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(MetricsValidation, NamesMustStartWithThrongPrefix) {
  MetricsRegistry reg;
  const std::string why = rejection([&] { reg.counter("ticks_total", "t"); });
  EXPECT_NE(why.find("ticks_total"), std::string::npos) << why;
  EXPECT_NE(why.find("throng_"), std::string::npos) << why;
  EXPECT_THROW(reg.gauge("Throng_x", "x"), std::invalid_argument);
  EXPECT_THROW(reg.histogram("", "x", {}), std::invalid_argument);
  EXPECT_NO_THROW(reg.counter("throng_ticks_total", "t"));
}

TEST(MetricsValidation, NamesMustBeValidPrometheusNamesWithoutColons) {
  MetricsRegistry reg;
  EXPECT_THROW(reg.counter("throng_bad-name", "x"), std::invalid_argument);
  EXPECT_THROW(reg.counter("throng_bad name", "x"), std::invalid_argument);
  EXPECT_THROW(reg.counter("throng_a:b", "x"), std::invalid_argument);  // colons are for recording rules
  EXPECT_THROW(reg.counter("throng_é", "x"), std::invalid_argument);
  EXPECT_NO_THROW(reg.counter("throng_Ok_123", "x"));
}

TEST(MetricsValidation, HelpMustNotBeEmpty) {
  MetricsRegistry reg;
  EXPECT_THROW(reg.counter("throng_x_total", ""), std::invalid_argument);
}

TEST(MetricsValidation, HelpMustNotHoldNewlineOrBackslash) {
  // prometheus-cpp writes HELP unescaped: either would garble the exposition.
  MetricsRegistry reg;
  const std::string why = rejection([&] { reg.counter("throng_x_total", "two\nlines"); });
  EXPECT_NE(why.find("throng_x_total"), std::string::npos) << why;
  EXPECT_THROW(reg.gauge("throng_y", "line one\nline two"), std::invalid_argument);
  EXPECT_THROW(reg.gauge("throng_z", "back\\slash"), std::invalid_argument);
  EXPECT_NO_THROW(reg.gauge("throng_w", "\"quotes\" are fine"));
}

TEST(MetricsValidation, LabelNames) {
  MetricsRegistry reg;
  EXPECT_THROW(reg.counter("throng_a_total", "a", {{"1abc", "v"}}), std::invalid_argument);
  EXPECT_THROW(reg.counter("throng_b_total", "b", {{"bad-name", "v"}}), std::invalid_argument);
  EXPECT_THROW(reg.counter("throng_c_total", "c", {{"", "v"}}), std::invalid_argument);
  EXPECT_THROW(reg.counter("throng_d_total", "d", {{"__reserved", "v"}}), std::invalid_argument);
  EXPECT_THROW(reg.counter("throng_e_total", "e", {{"k", "1"}, {"k", "2"}}), std::invalid_argument);
  EXPECT_THROW(reg.histogram("throng_f", "f", {1.0}, {{"le", "1"}}), std::invalid_argument);
  EXPECT_NO_THROW(reg.counter("throng_g_total", "g", {{"le", "fine on a counter"}}));
  EXPECT_NO_THROW(reg.counter("throng_h_total", "h", {{"_ok9", "any \"value\" \n is fine"}}));
}

TEST(MetricsValidation, FamilyMustAgreeOnTypeHelpAndLabelNames) {
  MetricsRegistry reg;
  reg.counter("throng_rejected_total", "Rejected.", {{"reason", "nan"}});
  EXPECT_THROW(reg.gauge("throng_rejected_total", "Rejected.", {{"reason", "x"}}), std::invalid_argument);
  EXPECT_THROW(reg.counter("throng_rejected_total", "Other help.", {{"reason", "x"}}), std::invalid_argument);
  EXPECT_THROW(reg.counter("throng_rejected_total", "Rejected.", {{"cause", "x"}}), std::invalid_argument);
  EXPECT_THROW(reg.counter("throng_rejected_total", "Rejected."), std::invalid_argument);
  EXPECT_NO_THROW(reg.counter("throng_rejected_total", "Rejected.", {{"reason", "speed"}}));
  const std::string why = rejection([&] { reg.histogram("throng_rejected_total", "Rejected.", {1.0}); });
  EXPECT_NE(why.find("throng_rejected_total"), std::string::npos) << why;
  EXPECT_NE(why.find("counter"), std::string::npos) << why;
}

TEST(MetricsValidation, LabelNamesMayComeInAnyOrder) {
  // Series render their labels sorted by name, so the order given makes no other family.
  MetricsRegistry reg;
  reg.counter("throng_bytes_total", "Bytes.", {{"dir", "out"}, {"topic", "snapshot"}});
  EXPECT_NO_THROW(reg.counter("throng_bytes_total", "Bytes.", {{"topic", "contacts"}, {"dir", "out"}}));
  EXPECT_THROW(reg.counter("throng_bytes_total", "Bytes.", {{"topic", "snapshot"}, {"dir", "out"}}),
               std::invalid_argument);  // the first series again
}

TEST(MetricsValidation, SameSeriesTwiceIsRejected) {
  MetricsRegistry reg;
  reg.counter("throng_x_total", "x", {{"k", "v"}});
  EXPECT_THROW(reg.counter("throng_x_total", "x", {{"k", "v"}}), std::invalid_argument);
  reg.gauge("throng_y", "y");
  EXPECT_THROW(reg.gauge("throng_y", "y"), std::invalid_argument);
}

TEST(MetricsValidation, HistogramSampleNamesCannotClash) {
  MetricsRegistry reg;
  reg.histogram("throng_latency", "l", {1.0});
  EXPECT_THROW(reg.counter("throng_latency_count", "c"), std::invalid_argument);
  EXPECT_THROW(reg.gauge("throng_latency_sum", "s"), std::invalid_argument);
  reg.counter("throng_queue_bucket", "b");
  EXPECT_THROW(reg.histogram("throng_queue", "q", {1.0}), std::invalid_argument);
}

TEST(MetricsValidation, HistogramBoundsFiniteAndStrictlyIncreasing) {
  MetricsRegistry reg;
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(reg.histogram("throng_a", "a", {1.0, 1.0}), std::invalid_argument);
  EXPECT_THROW(reg.histogram("throng_b", "b", {2.0, 1.0}), std::invalid_argument);
  EXPECT_THROW(reg.histogram("throng_c", "c", {1.0, inf}), std::invalid_argument);
  EXPECT_THROW(reg.histogram("throng_d", "d", {std::nan("")}), std::invalid_argument);
  EXPECT_NO_THROW(reg.histogram("throng_e", "e", {-1.0, 0.0, 1.0}));
  EXPECT_NO_THROW(reg.histogram("throng_f", "f", {}));  // only +Inf: legal, if not very useful
}

TEST(MetricsValidation, RejectedRegistrationLeavesNoTrace) {
  MetricsRegistry reg;
  EXPECT_THROW(reg.histogram("throng_bad", "b", {2.0, 1.0}), std::invalid_argument);
  EXPECT_THROW(reg.counter("throng_dup_total", "d", {{"k", "1"}, {"k", "2"}}), std::invalid_argument);
  EXPECT_THROW(reg.gauge("throng_help", "a\nb"), std::invalid_argument);
  EXPECT_THROW(reg.histogram("throng_le", "l", {1.0}, {{"le", "1"}}), std::invalid_argument);
  EXPECT_EQ(reg.render(), "");
  // A rejected series of an existing family leaves that family as it was.
  Counter& kept = reg.counter("throng_kept_total", "k", {{"k", "1"}});
  kept.inc(5);
  EXPECT_THROW(reg.counter("throng_kept_total", "k", {{"k", "1"}}), std::invalid_argument);
  EXPECT_THROW(reg.counter("throng_kept_total", "other help", {{"k", "2"}}), std::invalid_argument);
  const auto e = test::parse_exposition(reg.render());
  EXPECT_EQ(e.help.at("throng_kept_total"), "k");
  EXPECT_EQ(e.samples, (std::map<std::string, double>{{"throng_kept_total{k=\"1\"}", 5.0}}));
}

}  // namespace
}  // namespace throng::admin
