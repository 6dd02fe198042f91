// A planar wheel odometry's yaw calibrated from steps it measured again by scan matching, as a
// SLAM back end calibrates its odometry before trusting its covariance. The Intel log's raw
// odometry turns 0.032 rad too far per 0.55 m step on average (against the corrected poses;
// doc/loop_closure.md "Intel's graphs were folded"): a bias that grows with every step of a
// cycle, so an odometry check whose covariance grows with the square root of the steps (PCM's,
// eval/pairwise_consistency.hpp) refuses right loop edges. ROS-free; nothing here throws.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace eval {

// Yaw error of an odometry step (its yaw minus the measured one) = gain * (the step's yaw) +
// bias_per_m * (the step's length): a wheel-radius difference turns the robot in proportion to
// the distance driven, a track-width error in proportion to the turn.
struct OdometryYawModel {
  double gain = 0.0;        // [-] per radian the odometry turns
  double bias_per_m = 0.0;  // [rad/m] per metre the odometry drives
  int steps = 0;            // measured steps the fit used
  double rms_before = 0.0;  // [rad] yaw error of those steps as the odometry gave them
  double rms_after = 0.0;   // [rad] after the correction
};

// Least-squares fit of the model over the steps k -> k+1 that `measured` holds (measured[k]:
// the relative pose of pose k+1 in pose k's frame; size T_world_odom.size() - 1). False with
// *error when the sizes differ, fewer than `min_steps` (>= 2) steps are measured, or the
// measured steps do not tell the two terms apart (all straight, or all turning in proportion to
// their length).
bool fitOdometryYaw(const coral::Isometries& T_world_odom,
                    const std::vector<std::optional<Eigen::Isometry3d>>& measured, int min_steps,
                    OdometryYawModel* model, std::string* error);

// The odometry with every step's yaw corrected by the model (its translation kept, in the
// step's own start frame) and chained again from the first pose.
coral::Isometries correctOdometryYaw(const coral::Isometries& T_world_odom,
                                     const OdometryYawModel& model);

}  // namespace eval
}  // namespace coral_introspection
