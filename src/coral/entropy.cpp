#include "coral_introspection/coral/entropy.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace coral_introspection {
namespace coral {

namespace {
constexpr double kTwoPiE = 2.0 * M_PI * M_E;
constexpr double kRelativeEigenFloor = 1e-12;

// log(exp(a) + exp(b)) without overflow: det + epsilon in the log domain.
double logAddExp(double a, double b) {
  const double m = std::max(a, b);
  return m + std::log1p(std::exp(std::min(a, b) - m));
}
}  // namespace

bool differentialEntropy(const Mat3& sigma, int dim, double epsilon, double* h) {
  if (!sigma.allFinite()) return false;
  double eig_min = 0.0, eig_max = 0.0;
  Eigen::Vector3d ev = Eigen::Vector3d::Ones();
  if (dim == 2) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es;
    es.computeDirect(sigma.topLeftCorner<2, 2>(), Eigen::EigenvaluesOnly);  // closed form
    ev.head<2>() = es.eigenvalues();                                        // ascending
    eig_min = ev(0);
    eig_max = ev(1);
  } else {
    Eigen::SelfAdjointEigenSolver<Mat3> es;
    es.computeDirect(sigma, Eigen::EigenvaluesOnly);  // closed form, no iteration
    ev = es.eigenvalues();
    eig_min = ev(0);
    eig_max = ev(2);
  }
  if (!(eig_max > 0.0)) {
    // All points coincide (a repeated point gives exactly zero spread, the query being one
    // of them): no usable covariance. Never floored: the floor would be the same in the
    // separate and joint clouds and pull Q to 0 whatever the alignment.
    return false;
  }
  double log_det = 0.0;
  if (!(eig_min > kRelativeEigenFloor * eig_max)) {
    if (epsilon <= 0.0) return false;  // collinear / coplanar: no finite entropy
    log_det = std::log(epsilon);       // det ~ 0, so det + epsilon ~ epsilon
  } else {
    const double det = ev(0) * ev(1) * ev(2);  // ev(2) is 1 in 2D
    if (det >= std::numeric_limits<double>::min()) {
      // One logarithm: a neighbourhood lies within the radius (<= 10 m), so the product of
      // the eigenvalues neither overflows nor, checked here, underflows.
      log_det = std::log(det + std::max(epsilon, 0.0));  // Sec. III-C option (1) if epsilon > 0
    } else {
      // Tiny spread (< 1e-100 m): the product would underflow, the sum of logarithms does not.
      log_det = std::log(ev(0)) + std::log(ev(1)) + std::log(ev(2));
      if (epsilon > 0.0) log_det = logAddExp(log_det, std::log(epsilon));
    }
  }
  *h = 0.5 * (dim * std::log(kTwoPiE) + log_det);  // Eq. 1
  return std::isfinite(*h);
}

bool entropyOfPoints(const Points& pts, int dim, double epsilon, double* h) {
  if (pts.size() < static_cast<std::size_t>(dim) + 1) return false;
  Moments m;
  const Vec3 ref = pts.front();
  for (const Vec3& p : pts) {
    if (!p.allFinite()) return false;
    m.add(p - ref);
  }
  return differentialEntropy(m.covariance(), dim, epsilon, h);
}

}  // namespace coral
}  // namespace coral_introspection
