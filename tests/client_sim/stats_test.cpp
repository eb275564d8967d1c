#include <gtest/gtest.h>

#include <vector>

#include "throng/client_sim/stats.h"

namespace throng::client_sim {
namespace {

TEST(Stats, NearestRankPercentilesOfOneToHundred) {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i);  // unsorted on purpose
  const Summary s = summarize(v);
  EXPECT_EQ(s.count, 100u);
  EXPECT_DOUBLE_EQ(s.p50, 50);
  EXPECT_DOUBLE_EQ(s.p90, 90);
  EXPECT_DOUBLE_EQ(s.p99, 99);
  EXPECT_DOUBLE_EQ(s.max, 100);
  EXPECT_DOUBLE_EQ(s.mean, 50.5);
}

TEST(Stats, SmallSetsPickMeasuredValues) {
  const std::vector<double> v{10, 20, 30, 40};
  const Summary s = summarize(v);
  EXPECT_DOUBLE_EQ(s.p50, 20);  // rank ceil(0.5 * 4) = 2
  EXPECT_DOUBLE_EQ(s.p90, 40);  // rank ceil(3.6) = 4
  EXPECT_DOUBLE_EQ(s.p99, 40);
  EXPECT_DOUBLE_EQ(s.max, 40);
  const std::vector<double> sorted{10, 20, 30, 40};
  EXPECT_DOUBLE_EQ(percentile_sorted(sorted, 0), 10);
  EXPECT_DOUBLE_EQ(percentile_sorted(sorted, 25), 10);
  EXPECT_DOUBLE_EQ(percentile_sorted(sorted, 26), 20);
  EXPECT_DOUBLE_EQ(percentile_sorted(sorted, 100), 40);
}

TEST(Stats, EmptyAndSingle) {
  const Summary e = summarize(std::vector<double>{});
  EXPECT_EQ(e.count, 0u);
  EXPECT_EQ(e.p50, 0);
  EXPECT_EQ(e.max, 0);
  const Summary one = summarize(std::vector<double>{7.5});
  EXPECT_EQ(one.count, 1u);
  EXPECT_DOUBLE_EQ(one.p50, 7.5);
  EXPECT_DOUBLE_EQ(one.p99, 7.5);
  EXPECT_DOUBLE_EQ(one.max, 7.5);
}

TEST(Stats, SamplesAppendAndSummarize) {
  Samples a, b;
  for (int i = 1; i <= 50; ++i) a.add(i);
  for (int i = 51; i <= 100; ++i) b.add(i);
  a.append(b);
  EXPECT_EQ(a.size(), 100u);
  EXPECT_DOUBLE_EQ(a.summary().p99, 99);
  a.clear();
  EXPECT_TRUE(a.empty());
}

}  // namespace
}  // namespace throng::client_sim
