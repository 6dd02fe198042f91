#include "coral_introspection/rio/prior_factors.hpp"

namespace coral_introspection {
namespace rio {

StatePrior::StatePrior(const NavState& mean, const Mat15& sqrt_info)
    : mean_(mean), sqrt_info_(sqrt_info) {}

bool StatePrior::Evaluate(double const* const* parameters, double* residuals,
                          double** jacobians) const {
  Eigen::Map<const Vec3> p(parameters[0]);
  Eigen::Map<const Quat> q(parameters[0] + 3);
  Eigen::Map<const Eigen::Matrix<double, 9, 1>> sb(parameters[1]);
  Vec15 r;
  r.segment<3>(kP) = p - mean_.p;
  r.segment<3>(kR) = logQ(mean_.q.conjugate() * q);
  r.segment<3>(kV) = sb.segment<3>(0) - mean_.v;
  r.segment<3>(kBa) = sb.segment<3>(3) - mean_.ba;
  r.segment<3>(kBg) = sb.segment<3>(6) - mean_.bg;
  Eigen::Map<Vec15> res(residuals);
  res = sqrt_info_ * r;
  if (jacobians == nullptr) return true;
  if (jacobians[0]) {
    Eigen::Map<Eigen::Matrix<double, 15, 7, Eigen::RowMajor>> J(jacobians[0]);
    Eigen::Matrix<double, 15, 7> A = Eigen::Matrix<double, 15, 7>::Zero();
    A.block<3, 3>(kP, 0).setIdentity();
    A.block<3, 3>(kR, 3) = rightJacobianInverse(r.segment<3>(kR));
    J = sqrt_info_ * A;
  }
  if (jacobians[1]) {
    Eigen::Map<Eigen::Matrix<double, 15, 9, Eigen::RowMajor>> J(jacobians[1]);
    Eigen::Matrix<double, 15, 9> A = Eigen::Matrix<double, 15, 9>::Zero();
    A.block<9, 9>(kV, 0).setIdentity();
    J = sqrt_info_ * A;
  }
  return true;
}

bool ZeroVelocityFactor::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  Eigen::Map<Vec3> res(residuals);
  res = inv_sigma_ * Eigen::Map<const Vec3>(parameters[0]);
  if (jacobians && jacobians[0]) {
    Eigen::Map<Eigen::Matrix<double, 3, 9, Eigen::RowMajor>> J(jacobians[0]);
    J.setZero();
    J.block<3, 3>(0, 0) = inv_sigma_ * Mat3::Identity();
  }
  return true;
}

bool GyroBiasFactor::Evaluate(double const* const* parameters, double* residuals,
                              double** jacobians) const {
  Eigen::Map<Vec3> res(residuals);
  res = inv_sigma_ * (Eigen::Map<const Vec3>(parameters[0] + 6) - rate_);
  if (jacobians && jacobians[0]) {
    Eigen::Map<Eigen::Matrix<double, 3, 9, Eigen::RowMajor>> J(jacobians[0]);
    J.setZero();
    J.block<3, 3>(0, 6) = inv_sigma_ * Mat3::Identity();
  }
  return true;
}

}  // namespace rio
}  // namespace coral_introspection
