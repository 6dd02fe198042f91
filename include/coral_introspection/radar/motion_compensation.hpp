// Motion-distortion compensation of radar features with a constant-velocity model
// (paper Sec. V-A: "compensated for motion distortion effects as described in [1]").
#pragma once

#include "coral_introspection/coral/types.hpp"
#include "coral_introspection/radar/rip_features.hpp"

namespace coral_introspection {
namespace radar {

// Sensor velocity expressed in the sensor frame: m/s and rad/s.
struct Twist {
  coral::Vec3 linear = coral::Vec3::Zero();
  coral::Vec3 angular = coral::Vec3::Zero();
};

// Pose of the sensor at time t relative to its pose at t0 under constant body velocity:
// T_ref_t = exp((t - t0) * [v, w]) (SE(3) exponential).
Eigen::Isometry3d constantVelocityPose(const Twist& velocity, double dt);

// Inverse of the above: the constant body twist that moves the sensor by T_prev_curr (pose
// of the later scan in the earlier scan's frame) in dt seconds, log(T_prev_curr) / dt.
// dt <= 0 gives a zero twist.
Twist twistFromRelativePose(const Eigen::Isometry3d& T_prev_curr, double dt);

// Moves each point (measured at features->stamps[i]) into the sensor frame at ref_stamp:
// p_ref = T_ref_t(stamps[i] - ref_stamp) * p. Zero velocity leaves points unchanged.
// 2D features stay planar when the twist is planar (v_z = w_x = w_y = 0).
void compensateMotion(const Twist& velocity, double ref_stamp, RadarFeatures* features);

}  // namespace radar
}  // namespace coral_introspection
