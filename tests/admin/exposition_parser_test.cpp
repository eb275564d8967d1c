// The test parser itself must refuse what a scraper would refuse, or the render tests could pass
// on broken text.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include "exposition_parser.h"

namespace throng::admin::test {
namespace {

TEST(ExpositionParser, ReadsSamplesWithLabelsInAnyOrder) {
  const auto e = parse_exposition(
      "# HELP throng_h A \"help\".\n# TYPE throng_h histogram\n"
      "throng_h_bucket{z=\"a\\\\b\",le=\"+Inf\"} 3\nthrong_h_sum{z=\"a\\\\b\"} 1.5e+00\nthrong_h_count{z=\"a\\\\b\"} 3\n");
  EXPECT_EQ(e.help.at("throng_h"), "A \"help\".");
  EXPECT_EQ(e.value(series("throng_h_bucket", {{"le", "+Inf"}, {"z", "a\\b"}})), 3);
  EXPECT_EQ(e.value(series("throng_h_sum", {{"z", "a\\b"}})), 1.5);
  EXPECT_EQ(e.series_order.size(), 3u);
}

TEST(ExpositionParser, RefusesMalformedText) {
  EXPECT_NONFATAL_FAILURE(parse_exposition("throng_x 1\n"), "before its family's TYPE");
  EXPECT_NONFATAL_FAILURE(parse_exposition("# TYPE throng_x gauge\nthrong_x one\n"), "bad value");
  EXPECT_NONFATAL_FAILURE(parse_exposition("# TYPE throng_x gauge\nthrong_x 1"), "newline");
  EXPECT_NONFATAL_FAILURE(parse_exposition("# TYPE throng_x gauge\nthrong_x 1\nthrong_x 2\n"), "twice");
  EXPECT_NONFATAL_FAILURE(parse_exposition("# TYPE throng_x gauge\n# TYPE throng_x gauge\n"), "twice");
  // Whatever the parser calls it, the failure quotes the line it refused.
  EXPECT_NONFATAL_FAILURE(parse_exposition("# TYPE throng_x gauge\nthrong_x{a=\"q\"q\"} 1\n"), "throng_x{a=\"q\"q\"} 1");
  EXPECT_NONFATAL_FAILURE(parse_exposition("# TYPE throng_x gauge\nthrong_x{a=\"\\t\"} 1\n"), "bad escape");
  EXPECT_NONFATAL_FAILURE(parse_exposition("# TYPE throng_x counter\nthrong_x_count 1\n"), "TYPE");
  EXPECT_NONFATAL_FAILURE(
      parse_exposition("# TYPE throng_x gauge\n# TYPE throng_y gauge\nthrong_x 1\n"), "away from its family");
  EXPECT_NONFATAL_FAILURE(parse_exposition("# TYPE throng_x gauge\nthrong_x{a=\"1\",a=\"2\"} 1\n"), "twice");
}

}  // namespace
}  // namespace throng::admin::test
