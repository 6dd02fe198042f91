// Turns an input message (PointCloud2, or a polar radar image through the RIP front end)
// into points in the sensor frame, plus the small helpers the nodelet needs around it
// (velocity from two poses). Never throws: errors come back as false + message.
#pragma once

#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>

#include <string>
#include <vector>

#include "coral_introspection/radar/motion_compensation.hpp"
#include "coral_introspection/radar/rip_features.hpp"
#include "coral_introspection/ros/conversions.hpp"
#include "coral_introspection/ros/params.hpp"

namespace coral_introspection {
namespace ros_adapters {

struct SensorScan {
  core::RadarFeatures features;         // points in the sensor frame (+ per-point stamps and
                                        // intensity for radar features; empty otherwise)
  std::vector<double> radial_velocity;  // Doppler field of a cloud (same size) or empty
  std::size_t dropped_non_finite = 0;   // cloud points with NaN/Inf
  bool is_radar = false;
};

// PointCloud2 -> points (sensor frame). With cfg.doppler.enabled and the cloud holding
// doppler.velocity_field, the field is read into radial_velocity.
bool cloudToSensorScan(const sensor_msgs::PointCloud2& cloud, const NodeConfig& cfg,
                       SensorScan* out, std::string* error);

// mono8 polar image -> RIP features (sensor frame, not motion-compensated). Row stamps are
// shifted so that the scan reference time equals the header stamp (the time TF is looked
// up at), whatever the image's embedded clock (Oxford layout) says.
bool imageToSensorScan(const sensor_msgs::Image& image, const NodeConfig& cfg, SensorScan* out,
                       std::string* error);

// Constant body velocity that moves the sensor from T_fixed_prev to T_fixed_curr in dt
// seconds: the SE(3) logarithm of T_prev_curr divided by dt, in the sensor frame (the same
// twist in both frames). false for dt <= 0.
bool twistBetween(const Eigen::Isometry3d& T_fixed_prev, const Eigen::Isometry3d& T_fixed_curr,
                  double dt, core::Twist* twist);

// Component-wise median of the given twists (the latest one when fewer than three). Used to
// de-skew radar scans: the median of the last three inter-scan velocities ignores a single
// odometry jump, which would otherwise distort the scans next to it (2 m/s of false
// velocity for a 0.5 m jump at 4 Hz) and flag clean pairs.
core::Twist robustTwist(const std::vector<core::Twist>& recent);

}  // namespace ros_adapters
}  // namespace coral_introspection
