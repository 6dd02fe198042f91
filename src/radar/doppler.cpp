#include "coral_introspection/radar/doppler.hpp"

#include "coral_introspection/coral/validation.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "coral_introspection/radar/doppler_fit.hpp"

namespace coral_introspection {
namespace radar {

std::string DopplerConfig::validate() const {
  return coral::Problems()
      .require(sigma_doppler > 0.0, "sigma_doppler", "> 0 m/s", sigma_doppler)
      .require(ransac_threshold > 0.0, "ransac_threshold", "> 0 m/s", ransac_threshold)
      .require(ransac_iterations >= 1, "ransac_iterations", ">= 1", ransac_iterations)
      .require(min_inlier_ratio >= 0.0 && min_inlier_ratio <= 1.0, "min_inlier_ratio", "in [0, 1]",
               min_inlier_ratio)
      .require(min_points >= 3, "min_points", ">= 3", min_points)
      .require(confidence > 0.0 && confidence < 1.0, "confidence", "in (0, 1)", confidence)
      .require(sigma_reference_velocity >= 0.0, "sigma_reference_velocity", ">= 0 m/s",
               sigma_reference_velocity)
      .str();
}

EgoVelocityResult estimateEgoVelocity(const coral::Points& points,
                                      const std::vector<double>& radial_velocity,
                                      const DopplerConfig& cfg,
                                      const coral::Covariances* point_cov) {
  const DopplerFit fit = fitDoppler(points, radial_velocity, cfg, point_cov);
  EgoVelocityResult r;
  r.valid = fit.valid;
  r.error = fit.error;
  r.velocity = fit.velocity;
  r.num_points = fit.num_points;
  r.num_inliers = fit.inliers.size();
  r.inlier_ratio = fit.inlier_ratio;
  r.median_residual = fit.median_residual;
  r.planar = fit.dim == 2;
  if (fit.valid) {
    r.covariance.setZero();
    r.covariance.topLeftCorner(fit.dim, fit.dim) = fit.covariance;
    // z velocity of a planar scan is unobservable: infinite variance, value 0.
    if (r.planar) r.covariance(2, 2) = std::numeric_limits<double>::infinity();
  }
  return r;
}

ConsistencyResult checkVelocityConsistency(const coral::Points& points,
                                           const std::vector<double>& radial_velocity,
                                           const coral::Vec3& sensor_velocity,
                                           const DopplerConfig& cfg,
                                           const coral::Covariances* point_cov,
                                           const coral::Mat3* sensor_velocity_cov) {
  if (!sensor_velocity.allFinite() ||
      (sensor_velocity_cov != nullptr && !sensor_velocity_cov->allFinite())) {
    ConsistencyResult c;
    c.error = "sensor_velocity or its covariance is not finite";
    return c;
  }
  return testVelocity(fitDoppler(points, radial_velocity, cfg, point_cov), sensor_velocity, cfg,
                      sensor_velocity_cov);
}

ConsistencyResult testVelocity(const DopplerFit& fit, const coral::Vec3& sensor_velocity,
                               const DopplerConfig& cfg, const coral::Mat3* sensor_velocity_cov) {
  ConsistencyResult c;
  c.num_inliers = fit.inliers.size();
  c.velocity_doppler = fit.velocity;
  if (!fit.valid) {
    c.error = fit.error;
    return c;
  }
  const int n = fit.dim;
  // sum_k e_k(v)^2 / s_k^2 = sum_k e_k(v_D)^2 / s_k^2 + (v - v_D)^T I_D (v - v_D) for the
  // linear model of Eq. 9; the second term tests v. Its covariance I_D^-1 (built from the
  // Eq. 12 variances) is inflated by the reduced chi-square when the fit is noisier than
  // the configured sigma_doppler, and by the stated uncertainty of v itself.
  Eigen::MatrixXd S = std::max(1.0, fit.reduced_chi2) * fit.covariance;
  S.diagonal().array() += cfg.sigma_reference_velocity * cfg.sigma_reference_velocity;
  if (sensor_velocity_cov != nullptr) S += sensor_velocity_cov->topLeftCorner(n, n);
  const Eigen::VectorXd delta = (sensor_velocity - fit.velocity).head(n);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(S);
  if (ldlt.info() != Eigen::Success) {
    c.error = "Doppler velocity covariance is singular";
    return c;
  }
  c.chi2 = delta.dot(ldlt.solve(delta));
  c.dof = n;
  c.threshold = chiSquareQuantile(cfg.confidence, n);
  c.consistent = c.chi2 <= c.threshold;
  c.valid = std::isfinite(c.chi2);
  if (!c.valid) c.error = "chi-square statistic is not finite";
  return c;
}

namespace {
// Regularised lower incomplete gamma P(a, x): series for x < a + 1, else Lentz continued
// fraction for Q = 1 - P (standard expansions, converge in < 200 terms for a <= 50).
double gammaP(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_pref = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 500 && std::abs(term) > 1e-15 * std::abs(sum); ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return sum * std::exp(log_pref);
  }
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 500; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-15) break;
  }
  return 1.0 - std::exp(log_pref) * h;
}
}  // namespace

double chiSquareQuantile(double p, int dof) {
  p = std::clamp(p, 1e-12, 1.0 - 1e-12);
  const double a = 0.5 * std::max(1, dof);
  double lo = 0.0, hi = 10.0 * a + 100.0;
  for (int i = 0; i < 200; ++i) {  // bisection on the CDF P(dof/2, x/2)
    const double mid = 0.5 * (lo + hi);
    (gammaP(a, 0.5 * mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace radar
}  // namespace coral_introspection
