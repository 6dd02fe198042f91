#include "coral_introspection/rio/radar_factors.hpp"

#include <Eigen/Eigenvalues>

namespace coral_introspection {
namespace rio {

Mat3 whitening3(const Mat3& S, double min_eigenvalue) {
  Eigen::SelfAdjointEigenSolver<Mat3> es;
  es.computeDirect(0.5 * (S + S.transpose()));
  const Vec3 lambda = es.eigenvalues().cwiseMax(min_eigenvalue);
  return lambda.cwiseSqrt().cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
}

DopplerFactor::DopplerFactor(const Vec3& bearing, double m, const Vec3& omega,
                             const Extrinsics& ext, double weight)
    : dE_(ext.R * bearing), m_(m), omega_(omega), t_E_(ext.t), w_(weight) {}

bool DopplerFactor::Evaluate(double const* const* parameters, double* residuals,
                             double** jacobians) const {
  Eigen::Map<const Quat> q(parameters[0] + 3);
  Eigen::Map<const Vec3> v(parameters[1]), bg(parameters[1] + 6);
  const Mat3 RT = q.toRotationMatrix().transpose();
  const Vec3 v_body = RT * v;
  // Eq. 9: d^T R_E^T (v_body + (omega - b_g)^ t_E) - m; (R_E d)^T = d^T R_E^T.
  residuals[0] = w_ * (dE_.dot(v_body + (omega_ - bg).cross(t_E_)) - m_);
  if (jacobians == nullptr) return true;
  if (jacobians[0]) {  // pose: R_i^T v with R_i <- R_i Exp(dtheta) moves by [R_i^T v]^ dtheta
    Eigen::Map<Eigen::Matrix<double, 1, 7>> J(jacobians[0]);
    J.setZero();
    J.segment<3>(3) = w_ * dE_.transpose() * skew(v_body);
  }
  if (jacobians[1]) {  // speed_bias: v and b_g ((omega - b_g) x t = -t x (omega - b_g))
    Eigen::Map<Eigen::Matrix<double, 1, 9>> J(jacobians[1]);
    J.setZero();
    J.segment<3>(0) = w_ * dE_.transpose() * RT;
    J.segment<3>(6) = w_ * dE_.transpose() * skew(t_E_);
  }
  return true;
}

PointFactor::PointFactor(const Vec3& p, const Mat3& W, const Extrinsics& ext)
    : Wp_(W * p), W_RET_(W * ext.R.transpose()), t_E_(ext.t) {}

bool PointFactor::Evaluate(double const* const* parameters, double* residuals,
                           double** jacobians) const {
  Eigen::Map<const Vec3> pi(parameters[0]), l(parameters[1]);
  Eigen::Map<const Quat> q(parameters[0] + 3);
  const Mat3 RT = q.toRotationMatrix().transpose();
  const Vec3 l_body = RT * (l - pi);  // landmark in the body frame of frame i
  // Eq. 15 in the radar frame: R_E^T (l_body - t_E) - p_k, whitened by W (W R_E^T stored).
  Eigen::Map<Vec3> res(residuals);
  res = W_RET_ * (l_body - t_E_) - Wp_;
  if (jacobians == nullptr) return true;
  if (jacobians[0]) {
    Eigen::Map<Eigen::Matrix<double, 3, 7, Eigen::RowMajor>> J(jacobians[0]);
    J.setZero();
    J.block<3, 3>(0, 0) = -W_RET_ * RT;
    J.block<3, 3>(0, 3) = W_RET_ * skew(l_body);
  }
  if (jacobians[1]) {
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> J(jacobians[1]);
    J = W_RET_ * RT;
  }
  return true;
}

}  // namespace rio
}  // namespace coral_introspection
