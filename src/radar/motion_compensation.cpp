#include "coral_introspection/radar/motion_compensation.hpp"

#include <cmath>

namespace coral_introspection {
namespace radar {

namespace {
coral::Mat3 hat(const coral::Vec3& w) {
  coral::Mat3 m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}
}  // namespace

Eigen::Isometry3d constantVelocityPose(const Twist& velocity, double dt) {
  // SE(3) exponential of dt * [v, w]: R = exp([phi]x) (Rodrigues), t = V rho with
  // V = I + (1 - cos th)/th^2 [phi]x + (th - sin th)/th^3 [phi]x^2 (series for small th).
  const coral::Vec3 phi = velocity.angular * dt, rho = velocity.linear * dt;
  const double th2 = phi.squaredNorm(), th = std::sqrt(th2);
  const coral::Mat3 K = hat(phi), K2 = K * K;
  double a, b, c;  // sin th / th, (1 - cos th) / th^2, (th - sin th) / th^3
  if (th < 1e-4) {
    a = 1.0 - th2 / 6.0;
    b = 0.5 - th2 / 24.0;
    c = 1.0 / 6.0 - th2 / 120.0;
  } else {
    a = std::sin(th) / th;
    b = (1.0 - std::cos(th)) / th2;
    c = (th - std::sin(th)) / (th2 * th);
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = coral::Mat3::Identity() + a * K + b * K2;
  T.translation() = (coral::Mat3::Identity() + b * K + c * K2) * rho;
  return T;
}

Twist twistFromRelativePose(const Eigen::Isometry3d& T_prev_curr, double dt) {
  Twist out;
  if (!(dt > 0.0)) return out;
  // SE(3) logarithm: phi from the rotation, rho = V^-1 t with
  // V^-1 = I - 1/2 [phi]x + (1/th^2 - (1 + cos th) / (2 th sin th)) [phi]x^2.
  const Eigen::AngleAxisd aa(T_prev_curr.rotation());
  const coral::Vec3 phi = aa.axis() * aa.angle();
  const double th = phi.norm();
  const coral::Mat3 K = hat(phi);
  const double d = th < 1e-4 ? 1.0 / 12.0 + th * th / 720.0
                             : 1.0 / (th * th) - (1.0 + std::cos(th)) / (2.0 * th * std::sin(th));
  const coral::Vec3 rho =
      (coral::Mat3::Identity() - 0.5 * K + d * K * K) * T_prev_curr.translation();
  out.linear = rho / dt;
  out.angular = phi / dt;
  return out;
}

void compensateMotion(const Twist& velocity, double ref_stamp, RadarFeatures* features) {
  if (features == nullptr) return;
  if (velocity.linear.isZero(0.0) && velocity.angular.isZero(0.0)) return;
  if (!velocity.linear.allFinite() || !velocity.angular.allFinite()) return;
  coral::Points& pts = features->points;
  const std::size_t n = std::min(pts.size(), features->stamps.size());
  // Points of one azimuth share a stamp: compute T_ref_t once per distinct stamp.
  double last = std::nan("");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < n; ++i) {
    if (!(features->stamps[i] == last)) {
      last = features->stamps[i];
      T = constantVelocityPose(velocity, last - ref_stamp);  // pose at t in the ref frame
    }
    pts[i] = T * pts[i];
  }
}

}  // namespace radar
}  // namespace coral_introspection
