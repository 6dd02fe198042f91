#include "coral_introspection/ros/scan_source.hpp"

#include <ros/console.h>
#include <tf2_eigen/tf2_eigen.h>

#include "coral_introspection/ros/guarded.hpp"

namespace coral_introspection {
namespace ros_adapters {

ScanSource::ScanSource(ros::NodeHandle& nh, const NodeConfig& cfg, Stats* stats, Sink sink)
    : nh_(nh), cfg_(cfg), stats_(stats), sink_(std::move(sink)), tf_listener_(tf_buffer_, nh) {
  if (cfg_.input_type == InputType::kPointCloud)
    setUp(cloud_sub_, cloud_filter_);
  else
    setUp(image_sub_, image_filter_);
}

ScanSource::~ScanSource() {
  cloud_sub_.unsubscribe();  // inputs before the filters they feed
  image_sub_.unsubscribe();
  cloud_filter_.reset();
  image_filter_.reset();
}

std::string ScanSource::topic() const {
  return nh_.resolveName(cloud_filter_ ? "scan" : "polar_image");
}

void ScanSource::subscribe(bool on) {
  const auto queue = static_cast<uint32_t>(cfg_.queue_size);
  if (on && cloud_filter_) cloud_sub_.subscribe(nh_, "scan", queue);
  if (on && image_filter_) image_sub_.subscribe(nh_, "polar_image", queue);
  if (!on) {
    cloud_sub_.unsubscribe();
    image_sub_.unsubscribe();
  }
}

template <class M>
void ScanSource::setUp(message_filters::Subscriber<M>& sub,
                       std::shared_ptr<tf2_ros::MessageFilter<M>>& filter) {
  using Ptr = boost::shared_ptr<const M>;
  filter = std::make_shared<tf2_ros::MessageFilter<M>>(sub, tf_buffer_, cfg_.fixed_frame,
                                                       static_cast<uint32_t>(cfg_.queue_size), nh_);
  filter->registerCallback(boost::function<void(const Ptr&)>([this](const Ptr& m) { onScan(m); }));
  auto on_error = [this](const std::string& e) { problem(&InputCounters::errors, e); };
  filter->registerFailureCallback(boost::function<void(const Ptr&, tf2_ros::FilterFailureReason)>(
      [this, on_error](const Ptr& m, tf2_ros::FilterFailureReason r) {
        guarded(
            "TF failure callback",
            [&] {
              if (!stats_->resolvePending(m->header)) return;  // timed out (counted) already
              if (r == tf2_ros::filter_failure_reasons::EmptyFrameID)
                return problem(&InputCounters::bad_inputs,
                               "scan at t = " + std::to_string(m->header.stamp.toSec()) +
                                   " has an empty frame_id");
              noPose(m->header, r == tf2_ros::filter_failure_reasons::OutTheBack
                                    ? "older than the TF buffer (extrapolation into the past)"
                                    : "dropped from the TF queue while waiting");
            },
            on_error);
      }));
  // The filter queues its callbacks (callback queue of nh_), so the arrival is always
  // recorded before the scan or failure callback resolves it.
  sub.registerCallback(boost::function<void(const Ptr&)>([this, on_error](const Ptr& m) {
    guarded(
        "arrival callback", [&] { stats_->arrived(m->header); }, on_error);
  }));
}

template <class M>
void ScanSource::onScan(const boost::shared_ptr<const M>& msg) {
  guarded(
      "scan callback",
      [&] {
        stats_->resolvePending(msg->header);
        SensorScan s;
        std::string error;
        const bool ok = toSensorScan(*msg, cfg_, &s, &error);
        if (s.dropped_non_finite > 0) stats_->nonFinite(s.dropped_non_finite);
        if (!ok)
          return problem(&InputCounters::bad_inputs,
                         "bad input ('" + msg->header.frame_id + "' at t = " +
                             std::to_string(msg->header.stamp.toSec()) + "): " + error);
        try {
          s.scan.T_fixed_sensor = tf2::transformToEigen(tf_buffer_.lookupTransform(
              cfg_.fixed_frame, msg->header.frame_id, msg->header.stamp));
        } catch (const tf2::TransformException& e) {
          return noPose(msg->header, e.what());
        }
        sink_(std::move(s.scan), msg->header);
      },
      [this](const std::string& e) { problem(&InputCounters::errors, e); });
}

void ScanSource::expirePending() {
  for (const std_msgs::Header& h : stats_->expirePending(cfg_.tf_timeout))
    noPose(h, "not within tf_timeout = " + std::to_string(cfg_.tf_timeout) + " s");
}

void ScanSource::noPose(const std_msgs::Header& header, const std::string& error) {
  sink_(noPoseInput(header, cfg_.fixed_frame, error), header);
}

void ScanSource::problem(uint64_t InputCounters::*counter, const std::string& error) {
  stats_->count(counter, error);
  ROS_WARN_THROTTLE(5.0, "%s", error.c_str());
}

}  // namespace ros_adapters
}  // namespace coral_introspection
