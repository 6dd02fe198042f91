// CoralNodelet's publishers and how an Introspector report becomes messages. Costly outputs
// are lazy: the quality cloud (per-point CorAl) and the feature cloud are only computed
// while someone subscribes.
#pragma once

#include <ros/ros.h>

#include "coral_introspection/AlignmentQuality.h"
#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/ros/coral_params.hpp"

namespace coral_introspection {
namespace ros_adapters {

// AlignmentQuality::status of a report: a verdict, an invalid pair, not paired; without a
// pose NO_POSE when the input had none (TF failure), else REFUSED (empty scan).
uint8_t reportStatus(const online::Report& report, bool pose_failed);

class Outputs {
 public:
  // alignment, quality_cloud, features (+ velocity_consistency with Doppler); `cb` runs on
  // every (un)subscription.
  void advertise(ros::NodeHandle& nh, bool doppler, const ros::SubscriberStatusCallback& cb);
  bool subscribed() const;  // anyone listening to any output
  // What the Introspector must keep for the outputs someone listens to.
  online::ProcessOptions options(const NodeConfig& cfg, bool is_radar) const;
  // The scan's AlignmentQuality (stamped with the scan, in fixed_frame): the verdict or why
  // there is none (status, reason); with a verdict the quality cloud, with features the
  // feature cloud (sensor frame), with Doppler its check. `verdict`: the settings it was
  // judged with (tolerance and method are part of the message). Returns the latency [s]
  // written into the message (now - receipt).
  double publish(const online::Report& report, uint8_t status, const std_msgs::Header& scan_header,
                 const ros::Time& receipt, const std::string& fixed_frame,
                 const online::ProcessOptions& options, const coral::VerdictConfig& verdict) const;
  // The AlignmentQuality of a scan the Introspector never saw (refused, dropped).
  double publishNoVerdict(uint8_t status, const std::string& reason,
                          const std_msgs::Header& scan_header, const ros::Time& receipt,
                          const std::string& fixed_frame) const;

 private:
  double publishAlignment(AlignmentQuality m, const ros::Time& receipt) const;
  ros::Publisher alignment_, quality_, features_, doppler_;
};

}  // namespace ros_adapters
}  // namespace coral_introspection
