#include "coral_introspection/coral/logistic_regression.hpp"

#include "coral_introspection/coral/validation.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <string>

namespace coral_introspection {
namespace coral {

std::string LogisticRegressionConfig::validate() const {
  // The threshold is copied into the deployed ClassifierConfig: the same range applies.
  ClassifierConfig deployed;
  deployed.threshold = threshold;
  return Problems()
      .require(ridge >= 0.0 && std::isfinite(ridge), "ridge", "finite and >= 0", ridge)
      .require(max_iterations >= 1, "max_iterations", ">= 1", max_iterations)
      .require(tolerance > 0.0, "tolerance", "> 0", tolerance)
      .require(prior_weight >= 0.0 && std::isfinite(prior_weight), "prior_weight",
               "finite and >= 0", prior_weight)
      .require(prior_weight == 0.0 || prior_beta.allFinite(), "prior_beta", "finite",
               prior_beta.size() > 0 ? prior_beta(0) : 0.0)
      .nested("deployed classifier", deployed.validate())
      .str();
}

double LogisticModel::probability(const Eigen::VectorXd& x) const {
  return sigmoid(beta(0) + beta.tail(beta.size() - 1).dot(x));  // Eq. 9
}

ClassifierConfig LogisticModel::toClassifierConfig() const {
  ClassifierConfig c;
  c.beta0 = beta.size() > 0 ? beta(0) : 0.0;
  c.beta1 = beta.size() > 1 ? beta(1) : 0.0;
  c.beta2 = beta.size() > 2 ? beta(2) : 0.0;
  c.threshold = threshold;
  return c;
}

namespace {
// log(1 + e^z) without overflow.
double softplus(double z) {
  return z > 0.0 ? z + std::log1p(std::exp(-z)) : std::log1p(std::exp(z));
}

// Weighted negative log-likelihood + 0.5 sum_j P_j (b_j - m_j)^2 (ridge and prior in one
// quadratic; see fitLogisticRegression).
double objective(const Eigen::MatrixXd& Z, const Eigen::VectorXd& y, const Eigen::VectorXd& w,
                 const Eigen::VectorXd& b, const Eigen::VectorXd& P, const Eigen::VectorXd& m) {
  const Eigen::VectorXd z = Z * b;
  double f = 0.0;
  for (Eigen::Index i = 0; i < z.size(); ++i) f += w(i) * (softplus(z(i)) - y(i) * z(i));
  return f + 0.5 * (P.array() * (b - m).array().square()).sum();
}
}  // namespace

bool fitLogisticRegression(const Eigen::MatrixXd& X, const std::vector<int>& labels,
                           const std::vector<double>& sample_weights,
                           const LogisticRegressionConfig& cfg, LogisticModel* model,
                           std::string* error) {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (const std::string e = cfg.validate(); !e.empty()) return fail(e);
  const Eigen::Index n = X.rows(), d = X.cols();
  if (n == 0 || d == 0) return fail("empty design matrix");
  if (static_cast<Eigen::Index>(labels.size()) != n) return fail("labels and rows differ in count");
  if (!sample_weights.empty() && static_cast<Eigen::Index>(sample_weights.size()) != n)
    return fail("sample_weights and rows differ in count");
  if (!X.allFinite()) return fail("non-finite feature value");
  const bool prior = cfg.prior_weight > 0.0;
  if (prior && cfg.prior_beta.size() != d + 1)
    return fail("prior_beta needs " + std::to_string(d + 1) + " coefficients");

  Eigen::VectorXd y(n), w(n);
  double n_pos = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (labels[i] != 0 && labels[i] != 1) return fail("labels must be 0 or 1");
    y(i) = labels[i];
    n_pos += y(i);
    w(i) = sample_weights.empty() ? 1.0 : sample_weights[i];
    if (!(w(i) >= 0.0 && std::isfinite(w(i)))) return fail("sample weights must be finite, >= 0");
  }
  if (n_pos == 0.0 || n_pos == static_cast<double>(n)) return fail("both classes are needed");
  if (cfg.balanced)  // each class carries half of the weight (Sec. III-F)
    for (Eigen::Index i = 0; i < n; ++i)
      w(i) *= y(i) > 0.5 ? n / (2.0 * n_pos) : n / (2.0 * (n - n_pos));
  if (!(w.sum() > 0.0)) return fail("all weights are zero");
  w *= static_cast<double>(n) / w.sum();  // the ridge then has a sample-size-free meaning

  // Standardize so that one ridge and one tolerance fit features of any scale.
  const Eigen::RowVectorXd mu = X.colwise().mean();
  Eigen::RowVectorXd sd = ((X.rowwise() - mu).array().square().colwise().sum() / n).sqrt();
  Eigen::MatrixXd Z(n, d + 1);
  Z.col(0).setOnes();
  for (Eigen::Index j = 0; j < d; ++j) {
    if (!(sd(j) > 1e-12 * (1.0 + std::abs(mu(j))))) sd(j) = 0.0;  // constant column
    if (sd(j) > 0.0)
      Z.col(j + 1) = ((X.col(j).array() - mu(j)) / sd(j)).matrix();
    else
      Z.col(j + 1).setZero();
  }
  // Penalty on the slopes only (the intercept is free, as without a prior):
  // 0.5 ridge |b_s|^2 + 0.5 prior_weight |b_s - c|^2 = 0.5 sum_j P_j (b_j - m_j)^2 (+ const)
  // with P = ridge + prior_weight and m = prior_weight c / P; c_j = beta_j sd_j, the prior's
  // slopes in standardized coordinates.
  const double lambda = cfg.prior_weight;
  Eigen::VectorXd c = Eigen::VectorXd::Zero(d + 1);
  if (prior)
    for (Eigen::Index j = 0; j < d; ++j) c(j + 1) = cfg.prior_beta(j + 1) * sd(j);
  Eigen::VectorXd P = Eigen::VectorXd::Constant(d + 1, cfg.ridge + lambda);
  P(0) = 0.0;
  Eigen::VectorXd M = Eigen::VectorXd::Zero(d + 1);
  for (Eigen::Index j = 0; j <= d; ++j)
    if (P(j) > 0.0) M(j) = lambda * c(j) / P(j);
  for (Eigen::Index j = 0; j < d; ++j)
    if (sd(j) == 0.0) {  // pins the slope of a constant column at 0
      P(j + 1) = 1.0;
      M(j + 1) = 0.0;
    }

  Eigen::VectorXd b = prior ? M : Eigen::VectorXd::Zero(d + 1);  // start at the prior's slopes
  double f = objective(Z, y, w, b, P, M);
  LogisticModel m;
  m.threshold = cfg.threshold;
  for (int it = 1; it <= cfg.max_iterations; ++it) {
    m.iterations = it;
    // Newton / IRLS: gradient Z^T w (p - y) + P (b - M), Hessian Z^T W p(1-p) Z + diag(P).
    const Eigen::VectorXd z = Z * b;
    Eigen::VectorXd p(n), s(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      p(i) = sigmoid(z(i));
      s(i) = w(i) * p(i) * (1.0 - p(i));
    }
    const Eigen::VectorXd g =
        Z.transpose() * (w.array() * (p - y).array()).matrix() + P.cwiseProduct(b - M);
    Eigen::MatrixXd H = Z.transpose() * s.asDiagonal() * Z;
    H.diagonal() += P;
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(H);
    Eigen::VectorXd step = ldlt.solve(g);
    if (ldlt.info() != Eigen::Success || !step.allFinite())
      return fail("singular Hessian (separable data with ridge = 0?)");
    // Backtracking keeps every iteration a descent step far from the optimum.
    double t = 1.0, f_new = objective(Z, y, w, b - step, P, M);
    while (f_new > f + 1e-12 * std::abs(f) && t > 1e-8) {
      t *= 0.5;
      f_new = objective(Z, y, w, b - t * step, P, M);
    }
    b -= t * step;
    f = f_new;
    if ((t * step).cwiseAbs().maxCoeff() < cfg.tolerance) {
      m.converged = true;
      break;
    }
  }
  if (!b.allFinite()) return fail("fit diverged");
  // Back to raw features: beta_j = b_j / sd_j, beta0 = b0 - sum b_j mu_j / sd_j.
  m.beta.resize(d + 1);
  m.beta(0) = b(0);
  for (Eigen::Index j = 0; j < d; ++j) {
    // A constant column carries no information: it keeps the prior's slope (or 0).
    m.beta(j + 1) = sd(j) > 0.0 ? b(j + 1) / sd(j) : (prior ? cfg.prior_beta(j + 1) : 0.0);
    m.beta(0) -= m.beta(j + 1) * mu(j);
  }
  m.objective = f;
  *model = m;
  if (!m.converged && error) *error = "did not converge in max_iterations";
  return true;
}

}  // namespace coral
}  // namespace coral_introspection
