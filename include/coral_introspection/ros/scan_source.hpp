// The input side of CoralNodelet: subscribes `scan` (PointCloud2) or `polar_image` (mono8
// Image) through a tf2 MessageFilter, converts each message (scan_input.hpp), looks the
// sensor pose up at the stamp and hands the scan on. TF failures (from the filter, or a scan
// that waited longer than tf_timeout) are handed on as pose-less inputs; malformed messages
// are counted as bad inputs. Callbacks never throw.
#pragma once

#include <message_filters/subscriber.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>
#include <tf2_ros/transform_listener.h>

#include <functional>
#include <memory>

#include "coral_introspection/ros/diagnostics.hpp"
#include "coral_introspection/ros/scan_input.hpp"

namespace coral_introspection {
namespace ros_adapters {

class ScanSource {
 public:
  // scan: a converted scan (pose set, or unset with pose_error) and its message header.
  using Sink = std::function<void(online::ScanInput scan, const std_msgs::Header& header)>;
  // cfg: input_type, fixed_frame, queue_size, tf_timeout and the conversion parameters
  // (none of them reconfigurable). stats counts arrivals, bad inputs and errors.
  ScanSource(ros::NodeHandle& nh, const NodeConfig& cfg, Stats* stats, Sink sink);
  ~ScanSource();
  void subscribe(bool on);  // lazy input: only while an output has subscribers
  void expirePending();     // scans waiting for TF longer than tf_timeout: TF failures
  std::string topic() const;

 private:
  template <class M>
  void setUp(message_filters::Subscriber<M>& sub, std::shared_ptr<tf2_ros::MessageFilter<M>>& f);
  template <class M>
  void onScan(const boost::shared_ptr<const M>& msg);
  void noPose(const std_msgs::Header& header, const std::string& error);
  void problem(uint64_t InputCounters::*counter, const std::string& error);

  ros::NodeHandle nh_;
  const NodeConfig cfg_;
  Stats* stats_;
  Sink sink_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  message_filters::Subscriber<sensor_msgs::PointCloud2> cloud_sub_;
  message_filters::Subscriber<sensor_msgs::Image> image_sub_;
  std::shared_ptr<tf2_ros::MessageFilter<sensor_msgs::PointCloud2>> cloud_filter_;
  std::shared_ptr<tf2_ros::MessageFilter<sensor_msgs::Image>> image_filter_;
};

}  // namespace ros_adapters
}  // namespace coral_introspection
