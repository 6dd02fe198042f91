// Value types of the radar-inertial odometry (paper: radar_point_uncertainty_slam, Sec. III-A):
// IMU samples, radar frames with Doppler, and the per-frame navigation state
// x_i = (p_i, q_i, v_i, b_a, b_g) of Eq. 1. ROS-free (Eigen only).
#pragma once

#include <vector>

#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/rio/so3.hpp"

namespace coral_introspection {
namespace rio {

using coral::Points;

// One IMU sample in the body (IMU) frame. acc: specific force [m/s^2], gyro: [rad/s].
struct ImuSample {
  double t = 0.0;  // [s]
  Vec3 acc = Vec3::Zero();
  Vec3 gyro = Vec3::Zero();
};

// One radar scan, points in the radar frame (the frame of the sensor's point cloud).
struct RadarFrame {
  double t = 0.0;  // [s] measurement time, same clock as the IMU
  Points points;
  // Radial (Doppler) velocity per point [m/s]; empty when the sensor gives none.
  std::vector<double> radial_velocity;
  // Optional per-point intensity / SNR (same size as points, or empty).
  std::vector<double> intensity;
};

// State of one radar frame (Eq. 1): body pose in the odometry (world) frame, world
// velocity, accelerometer and gyroscope biases.
struct NavState {
  double t = 0.0;
  Vec3 p = Vec3::Zero();
  Quat q = Quat::Identity();  // R_world_body
  Vec3 v = Vec3::Zero();
  Vec3 ba = Vec3::Zero();
  Vec3 bg = Vec3::Zero();
};

// Parameter blocks as Ceres sees them: pose = (p, q.x, q.y, q.z, q.w), speed_bias = (v, ba, bg).
struct StateBlocks {
  double pose[7] = {0, 0, 0, 0, 0, 0, 1};
  double speed_bias[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
};

inline void toBlocks(const NavState& s, StateBlocks* b) {
  Eigen::Map<Vec3>(b->pose) = s.p;
  Eigen::Map<Eigen::Vector4d>(b->pose + 3) = s.q.normalized().coeffs();  // x, y, z, w
  Eigen::Map<Vec3>(b->speed_bias) = s.v;
  Eigen::Map<Vec3>(b->speed_bias + 3) = s.ba;
  Eigen::Map<Vec3>(b->speed_bias + 6) = s.bg;
}

inline void fromBlocks(const StateBlocks& b, NavState* s) {
  s->p = Eigen::Map<const Vec3>(b.pose);
  s->q = Eigen::Map<const Quat>(b.pose + 3).normalized();
  s->v = Eigen::Map<const Vec3>(b.speed_bias);
  s->ba = Eigen::Map<const Vec3>(b.speed_bias + 3);
  s->bg = Eigen::Map<const Vec3>(b.speed_bias + 6);
}

}  // namespace rio
}  // namespace coral_introspection
