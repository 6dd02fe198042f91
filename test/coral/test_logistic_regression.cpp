// Logistic regression (Sec. III-F) against an independent gradient-descent solve, a
// symmetric case with a known boundary, and the effect of class weights.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "coral_introspection/coral/logistic_regression.hpp"

using namespace coral_introspection::coral;

namespace {
// Overlapping 2-feature classes: the ML optimum is finite.
void makeData(int n_pos, int n_neg, unsigned seed, Eigen::MatrixXd* X, std::vector<int>* y) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  X->resize(n_pos + n_neg, 2);
  y->clear();
  for (int i = 0; i < n_pos + n_neg; ++i) {
    const bool pos = i < n_pos;
    (*X)(i, 0) = 5.0 + (pos ? -0.5 : 0.5) + 0.8 * g(rng);  // like H_joint [nats]
    (*X)(i, 1) = 4.8 + 0.3 * g(rng) + 0.2 * (*X)(i, 0);    // correlated, like H_sep
    y->push_back(pos ? 1 : 0);
  }
}

// Independent solver: plain full-batch gradient descent on the raw-feature weighted
// negative log-likelihood, step 1/L with L the Lipschitz bound of the gradient.
Eigen::VectorXd gradientDescent(const Eigen::MatrixXd& X, const std::vector<int>& y,
                                const Eigen::VectorXd& w) {
  const int n = X.rows();
  Eigen::MatrixXd Z(n, X.cols() + 1);
  Z << Eigen::VectorXd::Ones(n), X;
  const Eigen::MatrixXd A = Z.transpose() * w.asDiagonal() * Z;
  const double L =
      0.25 * Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A).eigenvalues().maxCoeff();
  Eigen::VectorXd b = Eigen::VectorXd::Zero(Z.cols());
  for (int it = 0; it < 3000000; ++it) {
    Eigen::VectorXd r(n);
    for (int i = 0; i < n; ++i) r(i) = w(i) * (1.0 / (1.0 + std::exp(-Z.row(i).dot(b))) - y[i]);
    const Eigen::VectorXd g = Z.transpose() * r;
    b -= g / L;
    if (g.norm() < 1e-11) break;
  }
  return b;
}
}  // namespace

TEST(LogisticRegression, MatchesGradientDescentTo1e6Unbalanced) {
  Eigen::MatrixXd X;
  std::vector<int> y;
  makeData(40, 60, 7, &X, &y);
  LogisticRegressionConfig cfg;
  cfg.balanced = false;
  cfg.ridge = 0.0;
  LogisticModel m;
  std::string err;
  ASSERT_TRUE(fitLogisticRegression(X, y, {}, cfg, &m, &err)) << err;
  EXPECT_TRUE(m.converged);
  const Eigen::VectorXd ref = gradientDescent(X, y, Eigen::VectorXd::Ones(100));
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(m.beta(j), ref(j), 1e-6) << "beta" << j;
}

TEST(LogisticRegression, BalancedWeightsMatchWeightedGradientDescent) {
  Eigen::MatrixXd X;
  std::vector<int> y;
  makeData(20, 80, 3, &X, &y);
  LogisticRegressionConfig cfg;
  cfg.ridge = 0.0;  // balanced = true: weights n / (2 n_class)
  LogisticModel m;
  std::string err;
  ASSERT_TRUE(fitLogisticRegression(X, y, {}, cfg, &m, &err)) << err;
  Eigen::VectorXd w(100);
  for (int i = 0; i < 100; ++i) w(i) = y[i] ? 100.0 / 40.0 : 100.0 / 160.0;
  const Eigen::VectorXd ref = gradientDescent(X, y, w);
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(m.beta(j), ref(j), 1e-6) << "beta" << j;
}

TEST(LogisticRegression, SymmetricOneDimensionalCaseHasBoundaryAtZero) {
  // Mirror-symmetric classes around x = 0 (with overlap): beta0 = 0 exactly, slope < 0.
  Eigen::MatrixXd X(8, 1);
  X << -3, -2, -1, 0.5, 3, 2, 1, -0.5;
  const std::vector<int> y = {1, 1, 1, 1, 0, 0, 0, 0};
  LogisticModel m;
  std::string err;
  LogisticRegressionConfig cfg;
  cfg.ridge = 0.0;
  ASSERT_TRUE(fitLogisticRegression(X, y, {}, cfg, &m, &err)) << err;
  EXPECT_NEAR(m.beta(0), 0.0, 1e-9);
  EXPECT_LT(m.beta(1), 0.0);
  Eigen::VectorXd x0(1);
  x0 << 0.0;
  EXPECT_NEAR(m.probability(x0), 0.5, 1e-9);
}

TEST(LogisticRegression, ClassWeightsShiftTheBoundaryTowardTheRareClass) {
  // 1D, 10 aligned vs 90 misaligned samples: unweighted, the boundary moves into the
  // aligned class (the majority dominates); balancing moves it back toward the middle.
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  Eigen::MatrixXd X(100, 1);
  std::vector<int> y;
  for (int i = 0; i < 100; ++i) {
    const bool pos = i < 10;
    X(i, 0) = (pos ? -1.0 : 1.0) + g(rng);
    y.push_back(pos);
  }
  LogisticRegressionConfig cfg;
  LogisticModel plain, balanced;
  std::string err;
  cfg.balanced = false;
  ASSERT_TRUE(fitLogisticRegression(X, y, {}, cfg, &plain, &err)) << err;
  cfg.balanced = true;
  ASSERT_TRUE(fitLogisticRegression(X, y, {}, cfg, &balanced, &err)) << err;
  const double b_plain = -plain.beta(0) / plain.beta(1);  // x where p = 0.5
  const double b_bal = -balanced.beta(0) / balanced.beta(1);
  EXPECT_LT(b_plain, b_bal - 0.3);  // unweighted: fewer samples called aligned
  EXPECT_NEAR(b_bal, 0.0, 0.6);
  // Explicit sample weights that equal the balancing reproduce the balanced fit.
  std::vector<double> w;
  for (int i = 0; i < 100; ++i) w.push_back(y[i] ? 9.0 : 1.0);
  LogisticModel manual;
  cfg.balanced = false;
  ASSERT_TRUE(fitLogisticRegression(X, y, w, cfg, &manual, &err)) << err;
  EXPECT_NEAR(manual.beta(0), balanced.beta(0), 1e-8);
  EXPECT_NEAR(manual.beta(1), balanced.beta(1), 1e-8);
}

TEST(LogisticRegression, SeparableDataStaysFiniteWithDefaultRidge) {
  Eigen::MatrixXd X(6, 2);
  X << 1, 1, 1.1, 0.9, 0.9, 1.2, 3, 1, 3.2, 0.8, 2.9, 1.1;  // H_joint larger = misaligned
  const std::vector<int> y = {1, 1, 1, 0, 0, 0};
  LogisticModel m;
  std::string err;
  ASSERT_TRUE(fitLogisticRegression(X, y, {}, LogisticRegressionConfig(), &m, &err)) << err;
  EXPECT_TRUE(m.converged);
  EXPECT_TRUE(m.beta.allFinite());
  for (int i = 0; i < 6; ++i) EXPECT_EQ(m.probability(X.row(i).transpose()) >= 0.5, y[i] == 1) << i;
  const ClassifierConfig c = m.toClassifierConfig();
  EXPECT_TRUE(c.validate().empty());
  EXPECT_EQ(classify(c, 1.0, 1.0).aligned, true);
  EXPECT_EQ(classify(c, 3.0, 1.0).aligned, false);
}

TEST(LogisticRegression, RejectsBadInput) {
  Eigen::MatrixXd X(3, 1);
  X << 1, 2, 3;
  LogisticModel m;
  std::string err;
  EXPECT_FALSE(fitLogisticRegression(X, {1, 1, 1}, {}, LogisticRegressionConfig(), &m, &err));
  EXPECT_NE(err.find("both classes"), std::string::npos);
  EXPECT_FALSE(fitLogisticRegression(X, {1, 0}, {}, LogisticRegressionConfig(), &m, &err));
  X(1, 0) = NAN;
  EXPECT_FALSE(fitLogisticRegression(X, {1, 0, 1}, {}, LogisticRegressionConfig(), &m, &err));
  LogisticRegressionConfig bad;
  bad.ridge = -1.0;
  EXPECT_NE(bad.validate().find("ridge"), std::string::npos);
}

// The Gaussian prior on the slopes (online self-calibration): a very strong prior returns the
// prior's raw slopes; a moderate one lands between the prior and the free fit; weight 0 gives
// exactly the free fit; a prior of the wrong size is refused.
TEST(LogisticRegression, GaussianPriorPullsTowardThePriorCoefficients) {
  Eigen::MatrixXd X;
  std::vector<int> y;
  makeData(30, 30, 21, &X, &y);
  LogisticRegressionConfig cfg;
  LogisticModel free_fit, strong, moderate;
  std::string err;
  ASSERT_TRUE(fitLogisticRegression(X, y, {}, cfg, &free_fit, &err)) << err;
  cfg.prior_beta = Eigen::Vector3d(2.0, -3.0, 2.5);
  cfg.prior_weight = 1e9;
  ASSERT_TRUE(fitLogisticRegression(X, y, {}, cfg, &strong, &err)) << err;
  for (int j = 1; j < 3; ++j) EXPECT_NEAR(strong.beta(j), cfg.prior_beta(j), 1e-5) << j;
  // The intercept stays free: with the prior's slopes it balances the classes, so the
  // weighted mean of p - y is 0 (the intercept's stationarity condition).
  double balance = 0.0;
  for (int i = 0; i < X.rows(); ++i) balance += strong.probability(X.row(i).transpose()) - y[i];
  EXPECT_NEAR(balance, 0.0, 1e-6);
  cfg.prior_weight = 20.0;
  ASSERT_TRUE(fitLogisticRegression(X, y, {}, cfg, &moderate, &err)) << err;
  EXPECT_TRUE(moderate.converged);
  const double d_free = (free_fit.beta - cfg.prior_beta).norm();
  const double d_mod = (moderate.beta - cfg.prior_beta).norm();
  EXPECT_LT(d_mod, 0.8 * d_free);
  EXPECT_GT((moderate.beta - free_fit.beta).norm(), 0.05 * d_free);
  cfg.prior_weight = 0.0;  // prior_beta ignored
  LogisticModel zero;
  ASSERT_TRUE(fitLogisticRegression(X, y, {}, cfg, &zero, &err)) << err;
  EXPECT_TRUE(zero.beta.isApprox(free_fit.beta, 1e-12));
  cfg.prior_weight = 1.0;
  cfg.prior_beta = Eigen::Vector2d(1.0, 1.0);  // wrong size for 2 features
  EXPECT_FALSE(fitLogisticRegression(X, y, {}, cfg, &zero, &err));
  EXPECT_NE(err.find("prior_beta needs 3"), std::string::npos) << err;
}
