// Oxford Radar RobotCar folder -> rosbag (polar images + ground-truth TF), shared by the
// oxford_to_bag tool and its tests.
#pragma once

#include <cstddef>
#include <string>

namespace coral_introspection {
namespace ros_eval {

struct OxfordBagOptions {
  std::string image_topic = "/radar/polar";  // sensor_msgs/Image, mono8, raw 400 x 3779 layout
  std::string tf_topic = "/tf";              // tf2_msgs/TFMessage
  std::string fixed_frame = "odom";          // parent frame of the TF (scan 0's radar pose)
  std::string radar_frame = "radar";         // image header.frame_id and TF child frame
  // The TF message is recorded this long before the image of the same stamp (its header
  // stamp is the scan stamp), so a replayed image always finds its TF.
  double tf_lead_s = 0.001;
};

struct OxfordBagSummary {
  std::size_t images = 0;
  std::size_t transforms = 0;
  double duration_s = 0.0;  // last scan stamp - first scan stamp
};

// Reads folder (radar/<stamp_us>.png, radar.timestamps, gt/radar_odometry.csv) and writes
// bag_path. Each PNG becomes one Image (header.stamp = scan stamp = PNG name, frame_id =
// radar_frame, data = the PNG bytes unchanged so the per-row metadata survives); each scan
// gets one TF fixed_frame -> radar_frame at its stamp, T_odom_radar(i) = T_0_1 * ... *
// T_{i-1}_i with T_{i-1}_i = se2(x, y, yaw) of the GT row source = i, destination = i-1.
// Never throws; false with *error (unreadable input, corrupt PNG, bag I/O failure).
bool writeOxfordBag(const std::string& folder, const std::string& bag_path,
                    const OxfordBagOptions& options, OxfordBagSummary* summary, std::string* error);

}  // namespace ros_eval
}  // namespace coral_introspection
