#include "coral_introspection/ros/coral_outputs.hpp"

#include <sensor_msgs/PointCloud2.h>

#include <algorithm>

#include "coral_introspection/ros/conversions.hpp"

namespace coral_introspection {
namespace ros_adapters {

uint8_t reportStatus(const online::Report& r, bool pose_failed) {
  if (r.judged)
    return r.pair.verdict.valid ? AlignmentQuality::VERDICT : AlignmentQuality::INVALID_PAIR;
  if (r.has_pose) return AlignmentQuality::NOT_PAIRED;
  return pose_failed ? AlignmentQuality::NO_POSE : AlignmentQuality::REFUSED;
}

void Outputs::advertise(ros::NodeHandle& nh, bool doppler,
                        const ros::SubscriberStatusCallback& cb) {
  // One message per input scan: a queue of a few seconds of scans.
  alignment_ = nh.advertise<AlignmentQuality>("alignment", 50, cb, cb);
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

double Outputs::publish(const online::Report& r, uint8_t status, const std_msgs::Header& h,
                        const ros::Time& receipt, const std::string& fixed_frame,
                        const online::ProcessOptions& o,
                        const coral::VerdictConfig& verdict) const {
  if (r.doppler && doppler_) doppler_.publish(toMessage(*r.doppler, h));
  if (o.keep_features && r.has_pose)
    features_.publish(pointsToCloud(r.features.points, h, &r.features.intensity));
  std_msgs::Header out;
  out.stamp = h.stamp;
  out.frame_id = fixed_frame;
  // The report's ids are the scans' header stamps in ns (ros_adapters::toSensorScan).
  AlignmentQuality m;
  if (r.judged) {
    m = toMessage(r.pair.verdict, verdict, out, ros::Time().fromNSec(r.id_ref), h.stamp);
    if (o.per_point)  // the pair is in the reference sensor frame
      quality_.publish(
          buildQualityCloud(r.pair.ref, r.pair.cur, r.pair.verdict.coral, out, r.T_fixed_ref));
  } else {
    m.header = out;
    m.stamp_b = h.stamp;
  }
  m.status = status;
  m.reason = r.reason;
  return publishAlignment(std::move(m), receipt);
}

double Outputs::publishNoVerdict(uint8_t status, const std::string& reason,
                                 const std_msgs::Header& h, const ros::Time& receipt,
                                 const std::string& fixed_frame) const {
  AlignmentQuality m;
  m.header.stamp = h.stamp;
  m.header.frame_id = fixed_frame;
  m.stamp_b = h.stamp;
  m.status = status;
  m.reason = reason;
  return publishAlignment(std::move(m), receipt);
}

double Outputs::publishAlignment(AlignmentQuality m, const ros::Time& receipt) const {
  // Latency in ROS time; negative only if ROS time jumped back meanwhile (bag loop).
  m.latency = receipt.isZero() ? 0.0 : std::max(0.0, (ros::Time::now() - receipt).toSec());
  alignment_.publish(m);
  return m.latency;
}

}  // namespace ros_adapters
}  // namespace coral_introspection
