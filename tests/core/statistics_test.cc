// DurationSummary: a run's timings in bounded memory (issue 33), against the exact
// quantiles of the same values.

#include "ocg/core/statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace ocg {
namespace {

TEST(DurationSummary, QuantilesWithinOnePercentCountSumAndMaximumExact) {
  std::mt19937 random(7);
  std::lognormal_distribution<double> duration(std::log(0.02), 1.0);  // about 20 ms
  std::vector<double> values;
  DurationSummary summary;
  double sum = 0.0;
  for (int i = 0; i < 50000; ++i) {
    const double seconds = duration(random);
    values.push_back(seconds);
    summary.Add(seconds);
    sum += seconds;
  }
  EXPECT_EQ(summary.count(), values.size());
  EXPECT_NEAR(summary.sum(), sum, 1e-9 * sum);
  EXPECT_DOUBLE_EQ(summary.max(), Quantile(values, 1.0));
  for (const double share : {0.0, 0.1, 0.5, 0.95, 0.99}) {
    const double exact = Quantile(values, share);
    EXPECT_NEAR(summary.Quantile(share), exact, 0.01 * exact) << share;
  }
}

TEST(DurationSummary, ZerosAndAnEmptySummary) {
  DurationSummary summary;
  EXPECT_EQ(summary.Median(), 0.0);
  EXPECT_EQ(summary.max(), 0.0);
  for (int i = 0; i < 10; ++i) summary.Add(0.0);
  summary.Add(0.5);
  EXPECT_EQ(summary.count(), 11u);
  EXPECT_EQ(summary.Median(), 0.0);  // most frames never wait for the map lock
  EXPECT_NEAR(summary.Quantile(1.0), 0.5, 0.005);
  EXPECT_LE(summary.Quantile(1.0), summary.max());
}

}  // namespace
}  // namespace ocg
