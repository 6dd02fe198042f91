// Core value types shared by every core module. ROS-free (Eigen only).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace coral_introspection {
namespace coral {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Points = std::vector<Vec3, Eigen::aligned_allocator<Vec3>>;
using Covariances = std::vector<Mat3, Eigen::aligned_allocator<Mat3>>;
using Isometries = std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>>;

// One scan expressed in some frame. For 2D data z is 0 (and ignored when dimension == 2).
struct Scan {
  Points points;
  // Sensor position of this scan, in the same frame as `points`. The dynamic radius of
  // CorAl (Sec. III-C option 2) is measured from here.
  Vec3 origin = Vec3::Zero();
  // Optional per-point measurement covariance (radar uncertainty model); empty if unknown.
  Covariances covariances;
};

// Applies T_dst_src to every point, the origin and the covariances (R S R^T).
Scan transformScan(const Scan& scan, const Eigen::Isometry3d& T_dst_src);

// SE(2) pose (x, y, yaw) as an Isometry3d rotating about z.
Eigen::Isometry3d se2(double x, double y, double yaw);

// Yaw [rad] of R: the angle about z of its x axis projected on the x-y plane (for R = Rz(yaw),
// the inverse of se2's rotation; for a 3D rotation, the heading of ZYX Euler angles).
double yawOf(const Eigen::Matrix3d& R);

}  // namespace coral
}  // namespace coral_introspection
