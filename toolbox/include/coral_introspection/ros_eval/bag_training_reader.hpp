// Training scans for coral_train from a rosbag: a scan topic (sensor_msgs/PointCloud2, or a
// polar radar sensor_msgs/Image through the RIP front end) plus accurate poses from /tf
// (+ /tf_static) or a nav_msgs/Odometry topic, looked up at each scan stamp.
#pragma once

#include <string>
#include <vector>

#include "coral_introspection/eval/training_set.hpp"
#include "coral_introspection/ros/coral_params.hpp"

namespace coral_introspection {
namespace ros_eval {

struct BagTrainingOptions {
  std::string scan_topic = "/scan";  // PointCloud2 or polar Image (type detected per message)
  // nav_msgs/Odometry topic (pose of child_frame_id in header.frame_id). Empty: poses come
  // from /tf. Odometry is added to the same transform buffer as /tf_static, so a static
  // base -> sensor extrinsic in the bag is applied automatically.
  std::string odom_topic;
  std::string fixed_frame = "odom";  // poses T_fixed_sensor are looked up in this frame
  ros_adapters::NodeConfig node;     // radar image decoding (polar_format, polar, rip)
  bool motion_compensation = true;   // radar images: de-skew with the pose-derived velocity
  bool with_cfear = true;            // radar images: also k-strongest points for CFEAR
  int cfear_k = 12;
  double cfear_z_min = 60.0;
  int max_scans = 0;             // 0 = all
  std::string validate() const;  // empty when valid
};

struct BagTrainingSummary {
  std::size_t scan_messages = 0;  // messages on scan_topic
  std::size_t no_pose = 0;        // skipped: no transform fixed_frame <- scan frame at the stamp
  std::size_t bad_message = 0;    // skipped: malformed cloud / image
  bool radar_images = false;      // the scan topic carried polar images
  std::string first_error;        // first skip reason, for the user
};

// Message type of `topic` in the bag ("sensor_msgs/Image", ...); empty when the bag cannot
// be opened or has no such topic. Lets coral_train pick radar defaults for polar images.
std::string bagTopicType(const std::string& bag_path, const std::string& topic);

// Reads the bag twice (poses, then scans). Scans without a pose are skipped and counted.
// Returns false with *error if the bag cannot be opened or fewer than 2 scans have a pose;
// never throws.
bool loadBagTrainingScans(const std::string& bag_path, const BagTrainingOptions& options,
                          const eval::Progress& progress, std::vector<eval::TrainingScan>* scans,
                          coral::Isometries* T_fixed_sensor, BagTrainingSummary* summary,
                          std::string* error);

}  // namespace ros_eval
}  // namespace coral_introspection
