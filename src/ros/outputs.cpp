#include "coral_introspection/ros/outputs.hpp"

#include <sensor_msgs/PointCloud2.h>

#include "coral_introspection/ros/conversions.hpp"

namespace coral_introspection {
namespace ros_adapters {

void Outputs::advertise(ros::NodeHandle& nh, bool doppler,
                        const ros::SubscriberStatusCallback& cb) {
  alignment_ = nh.advertise<AlignmentQuality>("alignment", 10, cb, cb);
  quality_ = nh.advertise<sensor_msgs::PointCloud2>("quality_cloud", 2, cb, cb);
  features_ = nh.advertise<sensor_msgs::PointCloud2>("features", 2, cb, cb);
  if (doppler) doppler_ = nh.advertise<VelocityConsistency>("velocity_consistency", 10, cb, cb);
}

bool Outputs::subscribed() const {
  return alignment_.getNumSubscribers() + quality_.getNumSubscribers() +
             features_.getNumSubscribers() + (doppler_ ? doppler_.getNumSubscribers() : 0) >
         0;
}

online::ProcessOptions Outputs::options(const NodeConfig& cfg, bool is_radar) const {
  online::ProcessOptions o;
  o.per_point = o.keep_scans = cfg.publish_quality_cloud && quality_.getNumSubscribers() > 0;
  o.keep_features = is_radar && cfg.publish_features && features_.getNumSubscribers() > 0;
  return o;
}

void Outputs::publish(const online::Report& r, const std_msgs::Header& h,
                      const std::string& fixed_frame, const online::ProcessOptions& o) const {
  if (r.doppler && doppler_) doppler_.publish(toMessage(*r.doppler, h));
  if (o.keep_features && r.has_pose)
    features_.publish(pointsToCloud(r.features.points, h, &r.features.intensity));
  if (!r.judged) return;
  std_msgs::Header out;
  out.stamp = h.stamp;
  out.frame_id = fixed_frame;
  // The report's ids are the scans' header stamps in ns (ros_adapters::toSensorScan).
  alignment_.publish(
      toMessage(r.pair.coral, r.pair.verdict, out, ros::Time().fromNSec(r.id_ref), h.stamp));
  if (o.per_point)  // the pair is in the reference sensor frame
    quality_.publish(buildQualityCloud(r.pair.ref, r.pair.cur, r.pair.coral, out, r.T_fixed_ref));
}

}  // namespace ros_adapters
}  // namespace coral_introspection
