// Accuracy, AUC (Mann-Whitney, ties = 1/2) and ROC on hand-computed examples.
#include <gtest/gtest.h>

#include <cmath>

#include "coral_introspection/coral/metrics.hpp"

using namespace coral_introspection::coral;

TEST(Metrics, AccuracyPlainAndBalanced) {
  // 3 positives (2 right), 1 negative (right): plain 3/4, balanced (2/3 + 1) / 2.
  const std::vector<double> s = {0.9, 0.6, 0.2, 0.1};
  const std::vector<int> y = {1, 1, 1, 0};
  EXPECT_DOUBLE_EQ(accuracy(s, y, 0.5, false), 0.75);
  EXPECT_DOUBLE_EQ(accuracy(s, y, 0.5, true), (2.0 / 3.0 + 1.0) / 2.0);
  // Threshold is inclusive (Eq. 10: aligned iff p >= t_h).
  EXPECT_DOUBLE_EQ(accuracy({0.5}, {1}, 0.5, false), 1.0);
  EXPECT_TRUE(std::isnan(accuracy({}, {}, 0.5, false)));
}

TEST(Metrics, AucHandComputedWithoutTies) {
  // Positives {0.8, 0.4}, negatives {0.6, 0.2}: pairs (0.8>0.6, 0.8>0.2, 0.4<0.6, 0.4>0.2)
  // -> 3 of 4.
  EXPECT_DOUBLE_EQ(auc({0.8, 0.4, 0.6, 0.2}, {1, 1, 0, 0}), 0.75);
  EXPECT_DOUBLE_EQ(auc({0.9, 0.8, 0.1}, {1, 1, 0}), 1.0);
  EXPECT_DOUBLE_EQ(auc({0.1, 0.2, 0.9}, {1, 1, 0}), 0.0);
}

TEST(Metrics, AucCountsTiesAsHalf) {
  // Positives {0.5, 0.7}, negatives {0.5, 0.3}: (0.5 vs 0.5 tie = 1/2) + 1 + 1 + 1 = 3.5/4.
  EXPECT_DOUBLE_EQ(auc({0.5, 0.7, 0.5, 0.3}, {1, 1, 0, 0}), 0.875);
  // All scores equal: 0.5.
  EXPECT_DOUBLE_EQ(auc({0.4, 0.4, 0.4}, {1, 0, 0}), 0.5);
  EXPECT_TRUE(std::isnan(auc({0.4, 0.3}, {1, 1})));
}

TEST(Metrics, RocCurvePointsAndTrapezoidEqualsAuc) {
  const std::vector<double> s = {0.5, 0.7, 0.5, 0.3};
  const std::vector<int> y = {1, 1, 0, 0};
  const auto roc = rocCurve(s, y);
  ASSERT_EQ(roc.size(), 4u);  // start + 3 distinct scores
  EXPECT_DOUBLE_EQ(roc[0].fpr, 0.0);
  EXPECT_DOUBLE_EQ(roc[0].tpr, 0.0);
  EXPECT_DOUBLE_EQ(roc[1].threshold, 0.7);
  EXPECT_DOUBLE_EQ(roc[1].tpr, 0.5);
  EXPECT_DOUBLE_EQ(roc[1].fpr, 0.0);
  EXPECT_DOUBLE_EQ(roc[2].tpr, 1.0);  // the tie moves diagonally
  EXPECT_DOUBLE_EQ(roc[2].fpr, 0.5);
  EXPECT_DOUBLE_EQ(roc[3].fpr, 1.0);
  double area = 0.0;
  for (std::size_t i = 1; i < roc.size(); ++i)
    area += (roc[i].fpr - roc[i - 1].fpr) * 0.5 * (roc[i].tpr + roc[i - 1].tpr);
  EXPECT_DOUBLE_EQ(area, auc(s, y));
}
