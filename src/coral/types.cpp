#include "coral_introspection/coral/types.hpp"

#include <cmath>

namespace coral_introspection {
namespace coral {

Scan transformScan(const Scan& scan, const Eigen::Isometry3d& T_dst_src) {
  Scan out;
  const Mat3 R = T_dst_src.linear();
  const Vec3 t = T_dst_src.translation();
  out.points.resize(scan.points.size());
  for (std::size_t i = 0; i < scan.points.size(); ++i)
    out.points[i].noalias() = R * scan.points[i] + t;
  out.origin = T_dst_src * scan.origin;
  out.covariances.reserve(scan.covariances.size());
  for (const Mat3& S : scan.covariances) out.covariances.push_back(R * S * R.transpose());
  return out;
}

Eigen::Isometry3d se2(double x, double y, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
  T.translation() = Vec3(x, y, 0.0);
  return T;
}

double yawOf(const Eigen::Matrix3d& R) { return std::atan2(R(1, 0), R(0, 0)); }

}  // namespace coral
}  // namespace coral_introspection
