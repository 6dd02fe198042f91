// Rotation helpers of the radar-inertial odometry: skew matrix, exponential and logarithm
// of SO(3) (as quaternions) and the right Jacobian of SO(3) with its inverse. Orientations
// are perturbed on the right everywhere in rio: R <- R Exp(delta).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace coral_introspection {
namespace rio {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

// [v]^ such that [v]^ u = v x u.
inline Mat3 skew(const Vec3& v) {
  Mat3 S;
  S << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return S;
}

// Exp(phi) as a unit quaternion (exact; second-order series near zero).
inline Quat expQ(const Vec3& phi) {
  const double theta = phi.norm();
  if (theta < 1e-8) {
    Quat q(1.0, 0.5 * phi.x(), 0.5 * phi.y(), 0.5 * phi.z());
    return q.normalized();
  }
  const Vec3 axis = phi / theta;
  const double s = std::sin(0.5 * theta);
  return Quat(std::cos(0.5 * theta), s * axis.x(), s * axis.y(), s * axis.z());
}

// Log(q) in (-pi, pi]; q and -q give the same rotation vector.
inline Vec3 logQ(const Quat& q_in) {
  Quat q = q_in.w() < 0.0 ? Quat(-q_in.w(), -q_in.x(), -q_in.y(), -q_in.z()) : q_in;
  const double n = q.vec().norm();
  if (n < 1e-10) return 2.0 * q.vec() / q.w();
  const double theta = 2.0 * std::atan2(n, q.w());
  return theta / n * q.vec();
}

// Right Jacobian of SO(3): Exp(phi + d) ~= Exp(phi) Exp(Jr(phi) d).
inline Mat3 rightJacobian(const Vec3& phi) {
  const double theta = phi.norm();
  const Mat3 W = skew(phi);
  if (theta < 1e-6) return Mat3::Identity() - 0.5 * W + W * W / 6.0;
  const double t2 = theta * theta;
  return Mat3::Identity() - (1.0 - std::cos(theta)) / t2 * W +
         (theta - std::sin(theta)) / (t2 * theta) * W * W;
}

// Inverse of the right Jacobian: Log(Exp(phi) Exp(d)) ~= phi + JrInv(phi) d.
inline Mat3 rightJacobianInverse(const Vec3& phi) {
  const double theta = phi.norm();
  const Mat3 W = skew(phi);
  if (theta < 1e-6) return Mat3::Identity() + 0.5 * W + W * W / 12.0;
  const double t2 = theta * theta;
  const double c = 1.0 / t2 - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta));
  return Mat3::Identity() + 0.5 * W + c * W * W;
}

}  // namespace rio
}  // namespace coral_introspection
