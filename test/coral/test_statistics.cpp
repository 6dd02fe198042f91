// median() and quantile() on hand-computed samples: odd and even sizes, unsorted input,
// ties, the empty sample (0) and NaN (NaN), and that quantile(v, 0.5) is the upper middle
// value, the "median" the radar front end and the evaluation reports have always used.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "coral_introspection/coral/statistics.hpp"

using namespace coral_introspection::coral;

namespace {
const double kNaN = std::numeric_limits<double>::quiet_NaN();
}

TEST(Statistics, MedianOfOddAndEvenSizes) {
  EXPECT_EQ(median({7.0}), 7.0);
  EXPECT_EQ(median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(median({4.0, 1.0, 3.0, 2.0}), 2.5);  // mean of the middle values 2 and 3
  EXPECT_EQ(median({5.0, -1.0}), 2.0);
  EXPECT_EQ(median({1.0, 2.0, 2.0, 9.0, 2.0}), 2.0);  // ties
  EXPECT_EQ(median({-std::numeric_limits<double>::infinity(), 0.0, 1.0}), 0.0);
}

TEST(Statistics, MedianEqualsTheSortedDefinitionOnRandomSamples) {
  // The copies this replaced sorted and averaged v[n/2 - 1] and v[n/2]: same bits.
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  for (std::size_t n = 1; n < 40; ++n) {
    std::vector<double> v(n);
    for (double& x : v) x = g(rng);
    std::vector<double> s = v;
    std::sort(s.begin(), s.end());
    const double sorted = n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
    EXPECT_EQ(median(v), sorted) << n;
    EXPECT_EQ(quantile(v, 0.5), s[n / 2]) << n;
  }
}

TEST(Statistics, QuantileIsASampleValueOfRoundedRank) {
  const std::vector<double> v = {50.0, 10.0, 40.0, 20.0, 30.0};  // sorted: 10 20 30 40 50
  EXPECT_EQ(quantile(v, 0.0), 10.0);
  EXPECT_EQ(quantile(v, 1.0), 50.0);
  EXPECT_EQ(quantile(v, 0.5), 30.0);
  EXPECT_EQ(quantile(v, 0.95), 50.0);                   // rank round(3.8) = 4
  EXPECT_EQ(quantile(v, 0.3), 20.0);                    // rank round(1.2) = 1
  EXPECT_EQ(quantile(v, 0.375), 30.0);                  // rank 1.5 rounds up
  EXPECT_EQ(quantile({4.0, 1.0, 3.0, 2.0}, 0.5), 3.0);  // even size: the upper middle value
  EXPECT_EQ(quantile(v, -1.0), 10.0);                   // q clamped to [0, 1]
  EXPECT_EQ(quantile(v, 2.0), 50.0);
}

TEST(Statistics, EmptySampleGivesZero) {
  EXPECT_EQ(median({}), 0.0);
  EXPECT_EQ(quantile({}, 0.5), 0.0);
}

TEST(Statistics, NaNAnywhereGivesNaN) {
  EXPECT_TRUE(std::isnan(median({kNaN})));
  EXPECT_TRUE(std::isnan(median({1.0, kNaN, 3.0})));
  EXPECT_TRUE(std::isnan(median({1.0, 2.0, 3.0, kNaN})));
  EXPECT_TRUE(std::isnan(quantile({kNaN, 1.0, 2.0}, 0.0)));
  EXPECT_TRUE(std::isnan(quantile({1.0, 2.0, kNaN}, 1.0)));
}
