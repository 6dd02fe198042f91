// CoralNodelet's publishers and how an Introspector report becomes messages. Costly outputs
// are lazy: the quality cloud (per-point CorAl) and the feature cloud are only computed
// while someone subscribes.
#pragma once

#include <ros/ros.h>

#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros/params.hpp"

namespace coral_introspection {
namespace ros_adapters {

class Outputs {
 public:
  // alignment, quality_cloud, features (+ velocity_consistency with Doppler); `cb` runs on
  // every (un)subscription.
  void advertise(ros::NodeHandle& nh, bool doppler, const ros::SubscriberStatusCallback& cb);
  bool subscribed() const;  // anyone listening to any output
  // What the Introspector must keep for the outputs someone listens to.
  online::ProcessOptions options(const NodeConfig& cfg, bool is_radar) const;
  // Verdict (stamped with the scan, in fixed_frame), quality cloud, features (sensor
  // frame) and Doppler check of one processed scan.
  void publish(const online::Report& report, const std_msgs::Header& scan_header,
               const std::string& fixed_frame, const online::ProcessOptions& options) const;

 private:
  ros::Publisher alignment_, quality_, features_, doppler_;
};

}  // namespace ros_adapters
}  // namespace coral_introspection
