// ROS-free reader of an Oxford Radar RobotCar style folder: radar/<stamp_us>.png,
// radar.timestamps and gt/radar_odometry.csv (see ../shared/data/README.md).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace coral_introspection {
namespace eval {

struct OxfordDataset {
  std::string folder;
  std::vector<int64_t> stamps_us;      // scan time stamps (= PNG names), in file order
  std::vector<std::string> png_paths;  // folder/radar/<stamp>.png
  // T_prev_curr[i] maps points of scan i (x = r cos a, y = r sin a) into scan i-1's frame,
  // from the GT row with source = stamps_us[i], destination = stamps_us[i-1]
  // (index 0 = identity). se2(x, y, yaw) of that row, as verified on the data.
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> T_prev_curr;

  // Reads radar.timestamps (valid == 1 scans whose PNG exists) and the GT. Fails when a
  // consecutive pair has no GT row, or files are missing / unreadable.
  bool load(const std::string& folder, std::string* error);
  // Accumulated pose of scan i in scan 0's frame: T_0_i = T_0_1 * ... * T_{i-1}_i.
  Eigen::Isometry3d T_first_scan(std::size_t i) const;
};

}  // namespace eval
}  // namespace coral_introspection
