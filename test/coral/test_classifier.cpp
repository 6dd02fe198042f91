// Logistic classifier of Eq. 9-10.
#include <gtest/gtest.h>

#include <cmath>

#include "coral_introspection/coral/classifier.hpp"

using namespace coral_introspection::coral;

TEST(Classifier, SigmoidIsStableAndSymmetric) {
  EXPECT_DOUBLE_EQ(sigmoid(0.0), 0.5);
  EXPECT_NEAR(sigmoid(2.0), 1.0 / (1.0 + std::exp(-2.0)), 1e-15);
  EXPECT_NEAR(sigmoid(-3.0) + sigmoid(3.0), 1.0, 1e-15);
  EXPECT_EQ(sigmoid(1000.0), 1.0);  // no overflow to NaN
  EXPECT_EQ(sigmoid(-1000.0), 0.0);
  EXPECT_FALSE(std::isnan(sigmoid(-800.0)));
}

TEST(Classifier, Eq9And10WithThreshold) {
  ClassifierConfig c;
  c.beta0 = 1.0;
  c.beta1 = -2.0;
  c.beta2 = 0.5;
  // z = 1 - 2*0.3 + 0.5*(-1) = -0.1
  Verdict v = classify(c, 0.3, -1.0);
  EXPECT_NEAR(v.probability, 1.0 / (1.0 + std::exp(0.1)), 1e-12);
  EXPECT_FALSE(v.aligned);  // p = 0.475 < 0.5
  c.threshold = 0.47;
  EXPECT_TRUE(classify(c, 0.3, -1.0).aligned);
  // p == threshold counts as aligned (Eq. 10 uses >=).
  c = ClassifierConfig();
  c.beta0 = c.beta1 = c.beta2 = 0.0;
  EXPECT_TRUE(classify(c, 5.0, 5.0).aligned);
}

TEST(Classifier, DefaultBoundaryIsOnQ) {
  const ClassifierConfig c;
  // Same Q, different scene entropy: same probability (only H_joint - H_sep matters).
  EXPECT_NEAR(classify(c, -4.0, -4.1).probability, classify(c, 2.0, 1.9).probability, 1e-12);
  EXPECT_TRUE(classify(c, -4.0, -4.05).aligned);
  EXPECT_FALSE(classify(c, -3.5, -4.0).aligned);
}

TEST(Classifier, ValidationRejectsBadValues) {
  ClassifierConfig c;
  EXPECT_EQ(c.validate(), "");
  c.threshold = 1.0;
  EXPECT_NE(c.validate().find("threshold"), std::string::npos);
  c = ClassifierConfig();
  c.beta1 = std::nan("");
  EXPECT_NE(c.validate().find("finite"), std::string::npos);
}
