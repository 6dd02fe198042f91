// Weighted logistic regression fitted by Newton / IRLS (paper Sec. III-F, Eq. 9-10): the
// self-supervised alignment classifier p = 1 / (1 + exp(-(beta0 + sum_j beta_j x_j))).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "coral_introspection/coral/classifier.hpp"

namespace coral_introspection {
namespace coral {

struct LogisticRegressionConfig {
  // Sample weights inversely proportional to class frequency (Sec. III-F: "weights of data
  // points were adjusted inversely proportional to class occurrence"): each class then
  // carries half of the total weight.
  bool balanced = true;
  // L2 penalty 0.5 * ridge * |beta_std|^2 on the slopes of the *standardized* features
  // (never on the intercept), with weights normalized to sum to the sample count. On
  // linearly separable data (CorAl at 0.7 m) the unpenalized optimum is at infinity and
  // Newton would diverge; 1e-3 keeps the slopes finite while changing non-separable fits
  // negligibly. 0 gives the plain maximum-likelihood fit.
  double ridge = 1e-3;
  // Gaussian prior on the slopes toward a known model (online self-calibration: the
  // configured classifier): 0.5 * prior_weight * |b_s - b_prior|^2 over the slopes in the
  // standardized coordinates of the fitted samples (slope per standard deviation of each
  // feature); the intercept stays free, so the boundary's position comes from the data and
  // its direction (how H_sep offsets H_joint, which samples from one scene hardly show)
  // from the prior until the data determine it. The data's curvature grows with the sample
  // count n (weights are normalized to sum to n), the prior's does not. 0 = no prior.
  // prior_beta: raw coefficients (intercept first, unused), size d + 1 when used.
  double prior_weight = 0.0;
  Eigen::VectorXd prior_beta;
  int max_iterations = 100;
  double tolerance = 1e-10;      // stop when the Newton step's max |delta beta_std| is below
  double threshold = 0.5;        // t_h of Eq. 10 copied into the ClassifierConfig
  std::string validate() const;  // empty when valid
};

struct LogisticModel {
  // beta[0] = intercept, beta[1..d] = slopes on the raw (unstandardized) features.
  Eigen::VectorXd beta;
  double threshold = 0.5;
  bool converged = false;
  int iterations = 0;
  double objective = 0.0;  // penalized weighted negative log-likelihood at the solution

  double probability(const Eigen::VectorXd& x) const;  // Eq. 9
  // The nodelet's 2-feature classifier (x1 = H_joint, x2 = H_sep). Needs beta.size() == 3
  // (a 1-feature model gets beta2 = 0).
  ClassifierConfig toClassifierConfig() const;
};

// Fits rows of X (n x d, d >= 1) to labels y (1 = aligned, 0 = misaligned). sample_weights
// may be empty (all 1); they multiply the class balancing weights. Returns false with
// *error on size mismatch, non-finite input, a single class, or an invalid config; never
// throws. A constant feature column gets slope 0 (the prior's slope when a prior is set).
bool fitLogisticRegression(const Eigen::MatrixXd& X, const std::vector<int>& y,
                           const std::vector<double>& sample_weights,
                           const LogisticRegressionConfig& cfg, LogisticModel* model,
                           std::string* error);

}  // namespace coral
}  // namespace coral_introspection
