#include "coral_introspection/rio/imu_factor.hpp"

namespace coral_introspection {
namespace rio {

namespace {
NavState stateFrom(const double* pose, const double* sb) {
  StateBlocks b;
  std::copy(pose, pose + 7, b.pose);
  std::copy(sb, sb + 9, b.speed_bias);
  NavState s;
  fromBlocks(b, &s);
  return s;
}
}  // namespace

bool ImuFactor::Evaluate(double const* const* parameters, double* residuals,
                         double** jacobians) const {
  const NavState si = stateFrom(parameters[0], parameters[1]);
  const NavState sj = stateFrom(parameters[2], parameters[3]);
  const Vec15 r = pre_->residual(si, sj);
  Eigen::Map<Vec15> res(residuals);
  const Mat15& W = pre_->sqrtInformation();
  res = W * r;
  if (jacobians == nullptr) return true;

  const double T = pre_->dt();
  const Vec3 g(0.0, 0.0, pre_->gravity());
  const Mat3 Ri = si.q.toRotationMatrix(), Rj = sj.q.toRotationMatrix();
  const Mat3 RiT = Ri.transpose();
  const Mat15& J = pre_->jacobian();
  const Mat3 Jr_inv = rightJacobianInverse(r.segment<3>(kR));
  // E = dq^T R_i^T R_j (dq bias-corrected); r_q = Log(E).
  const Vec3 phi = J.block<3, 3>(kR, kBg) * (si.bg - pre_->linearizedBg());
  const Mat3 E = (pre_->deltaQ() * expQ(phi)).toRotationMatrix().transpose() * RiT * Rj;

  if (jacobians[0]) {  // pose_i: (dp_i, dtheta_i)
    Eigen::Map<Eigen::Matrix<double, 15, 7, Eigen::RowMajor>> Jp(jacobians[0]);
    Eigen::Matrix<double, 15, 7> A = Eigen::Matrix<double, 15, 7>::Zero();
    A.block<3, 3>(kP, 0) = -RiT;
    A.block<3, 3>(kP, 3) = skew(RiT * (sj.p - si.p - si.v * T + 0.5 * g * T * T));
    A.block<3, 3>(kR, 3) = -Jr_inv * Rj.transpose() * Ri;
    A.block<3, 3>(kV, 3) = skew(RiT * (sj.v - si.v + g * T));
    Jp = W * A;
  }
  if (jacobians[1]) {  // speed_bias_i: (dv_i, dba_i, dbg_i)
    Eigen::Map<Eigen::Matrix<double, 15, 9, Eigen::RowMajor>> Jsb(jacobians[1]);
    Eigen::Matrix<double, 15, 9> A = Eigen::Matrix<double, 15, 9>::Zero();
    A.block<3, 3>(kP, 0) = -RiT * T;
    A.block<3, 3>(kP, 3) = -J.block<3, 3>(kP, kBa);
    A.block<3, 3>(kP, 6) = -J.block<3, 3>(kP, kBg);
    A.block<3, 3>(kR, 6) = -Jr_inv * E.transpose() * rightJacobian(phi) * J.block<3, 3>(kR, kBg);
    A.block<3, 3>(kV, 0) = -RiT;
    A.block<3, 3>(kV, 3) = -J.block<3, 3>(kV, kBa);
    A.block<3, 3>(kV, 6) = -J.block<3, 3>(kV, kBg);
    A.block<3, 3>(kBa, 3) = -Mat3::Identity();
    A.block<3, 3>(kBg, 6) = -Mat3::Identity();
    Jsb = W * A;
  }
  if (jacobians[2]) {  // pose_j
    Eigen::Map<Eigen::Matrix<double, 15, 7, Eigen::RowMajor>> Jp(jacobians[2]);
    Eigen::Matrix<double, 15, 7> A = Eigen::Matrix<double, 15, 7>::Zero();
    A.block<3, 3>(kP, 0) = RiT;
    A.block<3, 3>(kR, 3) = Jr_inv;
    Jp = W * A;
  }
  if (jacobians[3]) {  // speed_bias_j
    Eigen::Map<Eigen::Matrix<double, 15, 9, Eigen::RowMajor>> Jsb(jacobians[3]);
    Eigen::Matrix<double, 15, 9> A = Eigen::Matrix<double, 15, 9>::Zero();
    A.block<3, 3>(kV, 0) = RiT;
    A.block<3, 3>(kBa, 3) = Mat3::Identity();
    A.block<3, 3>(kBg, 6) = Mat3::Identity();
    Jsb = W * A;
  }
  return true;
}

}  // namespace rio
}  // namespace coral_introspection
