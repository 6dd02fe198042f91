#include "coral_introspection/rio/pose_manifold.hpp"

#include "coral_introspection/rio/so3.hpp"

namespace coral_introspection {
namespace rio {

bool PoseManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  Eigen::Map<const Vec3> p(x), dp(delta), dth(delta + 3);
  Eigen::Map<const Quat> q(x + 3);
  Eigen::Map<Vec3> p_out(x_plus_delta);
  Eigen::Map<Quat> q_out(x_plus_delta + 3);
  p_out = p + dp;
  q_out = (q * expQ(dth)).normalized();
  return true;
}

bool PoseManifold::PlusJacobian(const double*, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.topRows<6>().setIdentity();
  return true;
}

bool PoseManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  Eigen::Map<const Vec3> py(y), px(x);
  Eigen::Map<const Quat> qy(y + 3), qx(x + 3);
  Eigen::Map<Vec3> d(y_minus_x);
  d = py - px;
  Eigen::Map<Vec3> dth(y_minus_x + 3);
  dth = logQ(qx.conjugate() * qy);
  return true;
}

bool PoseManifold::MinusJacobian(const double*, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.leftCols<6>().setIdentity();
  return true;
}

}  // namespace rio
}  // namespace coral_introspection
