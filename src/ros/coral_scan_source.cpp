#include "coral_introspection/ros/coral_scan_source.hpp"

#include <ros/console.h>
#include <ros/master.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>

#include "coral_introspection/ros/guarded.hpp"

namespace coral_introspection {
namespace ros_adapters {

namespace {
std::string describe(const std_msgs::Header& h) {
  return "'" + h.frame_id + "' at t = " + std::to_string(h.stamp.toSec());
}
}  // namespace

std::string inputTopicTypeError(const std::string& topic, const std::string& published_type,
                                InputType type) {
  const std::string cloud = ros::message_traits::DataType<sensor_msgs::PointCloud2>::value(),
                    laser = ros::message_traits::DataType<sensor_msgs::LaserScan>::value();
  std::string wanted, hint;
  switch (type) {
    case InputType::kPolarImage:
      wanted = ros::message_traits::DataType<sensor_msgs::Image>::value();
      hint =
          "remap polar_image to a mono8 polar image topic, or set input_type pointcloud and "
          "remap scan";
      break;
    case InputType::kLaserScan:
      wanted = laser;
      hint = published_type == cloud ? "set input_type pointcloud for PointCloud2"
                                     : "remap scan to a LaserScan topic";
      break;
    default:
      wanted = cloud;
      hint = published_type == laser ? "set input_type laser_scan (and config/lidar_2d.yaml) for "
                                       "LaserScan"
                                     : "remap scan to a PointCloud2 topic, or set input_type "
                                       "polar_image and remap polar_image";
  }
  if (published_type.empty() || published_type == wanted) return "";
  return "input topic " + topic + " carries " + published_type +
         ", but this nodelet is configured for " + inputKindName(type) + " and reads " + wanted +
         " there: roscpp drops the connection, no scan arrives (" + hint + ")";
}

ScanSource::ScanSource(ros::NodeHandle& nh, const NodeConfig& cfg, Stats* stats, Sink sink)
    : nh_(nh),
      cfg_(cfg),
      stats_(stats),
      sink_(std::move(sink)),
      tf_feed_(nh, &tf_buffer_, [this](const std::string& why) {
        stats_->tfCleared();
        ROS_INFO_THROTTLE(10.0, "%s", why.c_str());
      }) {
  if (cfg_.input_type == InputType::kPointCloud)
    setUp(cloud_sub_, cloud_filter_);
  else if (cfg_.input_type == InputType::kLaserScan)
    setUp(laser_sub_, laser_filter_);
  else
    setUp(image_sub_, image_filter_);
}

ScanSource::~ScanSource() {
  cloud_sub_.unsubscribe();  // inputs before the filters they feed
  image_sub_.unsubscribe();
  laser_sub_.unsubscribe();
  cloud_filter_.reset();
  image_filter_.reset();
  laser_filter_.reset();
}

std::string ScanSource::topic() const {
  return nh_.resolveName(image_filter_ ? "polar_image" : "scan");
}

void ScanSource::subscribe(bool on) {
  // The subscriber queue only has to absorb scheduling jitter: the callbacks convert and
  // hand on (no CorAl), and overload is handled (and counted) by the worker's mailbox.
  const auto queue = static_cast<uint32_t>(cfg_.queue_size);
  subscribed_ = on;
  if (on && cloud_filter_) cloud_sub_.subscribe(nh_, "scan", queue);
  if (on && image_filter_) image_sub_.subscribe(nh_, "polar_image", queue);
  if (on && laser_filter_) laser_sub_.subscribe(nh_, "scan", queue);
  if (!on) {
    cloud_sub_.unsubscribe();
    image_sub_.unsubscribe();
    laser_sub_.unsubscribe();
    stats_->inputStopped();
  }
}

// subscriber -> onArrival (count, refuse stamp 0, time jumps) -> MessageFilter (waits for
// TF, queued on nh_'s callback queue) -> onScan / onFailure.
template <class M>
void ScanSource::setUp(message_filters::Subscriber<M>& sub,
                       std::shared_ptr<tf2_ros::MessageFilter<M>>& filter) {
  filter = std::make_shared<tf2_ros::MessageFilter<M>>(tf_buffer_, cfg_.fixed_frame,
                                                       static_cast<uint32_t>(cfg_.queue_size), nh_);
  filter->registerCallback(
      boost::function<void(const Event<M>&)>([this](const Event<M>& e) { onScan(e); }));
  filter->registerFailureCallback(
      boost::function<void(const boost::shared_ptr<const M>&, tf2_ros::FilterFailureReason)>(
          [this](const boost::shared_ptr<const M>& m, tf2_ros::FilterFailureReason r) {
            onFailure(Event<M>(m, ros::Time()), r);
          }));
  tf2_ros::MessageFilter<M>* f = filter.get();
  sub.registerCallback(
      boost::function<void(const Event<M>&)>([this, f](const Event<M>& e) { onArrival(e, *f); }));
}

template <class M>
void ScanSource::onArrival(const Event<M>& event, tf2_ros::MessageFilter<M>& filter) {
  guarded(
      "arrival callback",
      [&] {
        const std_msgs::Header& h = event.getMessage()->header;
        stats_->arrived(h, event.getPublisherName());
        // TF at time 0 means "latest": an unstamped scan would be judged with whatever pose
        // is newest and would spoil the next pair too.
        if (h.stamp.isZero())
          return refuse(h, event.getReceiptTime(), &InputCounters::unstamped,
                        "scan " + describe(h) + " refused: header.stamp is 0 (unset)");
        if (scan_jumps_.offer(h.frame_id, h.stamp.toSec()))
          tf_feed_.clearBefore(h.stamp.toSec(), "scan " + describe(h) +
                                                    " jumped back in time (looping bag?): TF "
                                                    "buffer cleared");
        stats_->waitForTf(h, event.getReceiptTime());
        // A scan of before a time jump whose transforms were cleared (the next loop's TF
        // overtook it): posed from the snapshot at once, it would wait in vain otherwise.
        // Otherwise it waits for TF, added under the feed's lock (no clear in between).
        geometry_msgs::TransformStamped before;
        if (tf_feed_.lookupBeforeJumpOrWait(cfg_.fixed_frame, h.frame_id, h.stamp, &before,
                                            [&] { filter.add(event); }))
          onScan(event);
      },
      [this](const std::string& e) { countError(e); });
}

template <class M>
void ScanSource::onFailure(const Event<M>& event, tf2_ros::FilterFailureReason r) {
  guarded(
      "TF failure callback",
      [&] {
        const std_msgs::Header& h = event.getMessage()->header;
        const std::optional<ros::Time> receipt = stats_->resolvePending(h);
        if (!receipt) return;  // timed out (counted) already
        if (r == tf2_ros::filter_failure_reasons::EmptyFrameID)
          return refuse(
              h, *receipt, &InputCounters::bad_inputs,
              "scan at t = " + std::to_string(h.stamp.toSec()) + " refused: empty frame_id");
        noPose(h, *receipt,
               r == tf2_ros::filter_failure_reasons::OutTheBack
                   ? "older than the TF buffer (extrapolation into the past)"
                   : "dropped from the TF queue (queue_size scans waited for TF)");
      },
      [this](const std::string& e) { countError(e); });
}

template <class M>
void ScanSource::onScan(const Event<M>& event) {
  guarded(
      "scan callback",
      [&] {
        const M& msg = *event.getMessage();
        const std::optional<ros::Time> receipt = stats_->resolvePending(msg.header);
        if (!receipt) {  // reported as a TF failure at tf_timeout: not judged now
          stats_->late();
          ROS_WARN_THROTTLE(5.0,
                            "TF for scan %s arrived after tf_timeout = %.3g s: not judged (it "
                            "was reported as a TF failure; raise tf_timeout if this repeats)",
                            describe(msg.header).c_str(), cfg_.tf_timeout);
          return;
        }
        SensorScan s;
        std::string error;
        const bool ok = toSensorScan(msg, cfg_, &s, &error);
        if (s.dropped_non_finite > 0) stats_->nonFinite(s.dropped_non_finite);
        if (!ok)
          return refuse(msg.header, *receipt, &InputCounters::bad_inputs,
                        "bad input (" + describe(msg.header) + "): " + error);
        try {
          // Before-the-jump first: after a clear the live buffer no longer has its pose.
          geometry_msgs::TransformStamped t;
          if (!tf_feed_.lookupBeforeJump(cfg_.fixed_frame, msg.header.frame_id, msg.header.stamp,
                                         &t))
            t = tf_buffer_.lookupTransform(cfg_.fixed_frame, msg.header.frame_id, msg.header.stamp);
          s.scan.T_fixed_sensor = tf2::transformToEigen(t);
        } catch (const tf2::TransformException& e) {
          return noPose(msg.header, *receipt, e.what());
        }
        ScanEvent out;
        out.scan = std::move(s.scan);
        out.header = msg.header;
        out.receipt = *receipt;
        sink_(std::move(out));
      },
      [this](const std::string& e) { countError(e); });
}

void ScanSource::expirePending() {
  for (const auto& [header, receipt] : stats_->expirePending(cfg_.tf_timeout))
    noPose(header, receipt, "not within tf_timeout = " + std::to_string(cfg_.tf_timeout) + " s");
}

void ScanSource::checkInputTopic() {
  ros::master::V_TopicInfo topics;
  if (!subscribed_ || !ros::master::getTopics(topics)) return;  // no master: nothing to tell
  // The master keeps one type per topic, the last publisher's (a subscriber sets it only
  // for a topic nobody published yet), so a publisher of another type shows here.
  const std::string name = topic();
  std::string published;
  for (const ros::master::TopicInfo& t : topics)
    if (t.name == name) published = t.datatype;
  const std::string error = inputTopicTypeError(name, published, cfg_.input_type);
  if (error == topic_type_error_) return;
  topic_type_error_ = error;
  stats_->inputTopicProblem(error);
  if (error.empty()) {
    ROS_INFO("input topic %s: no publisher of another message type any more", name.c_str());
    return;
  }
  std_msgs::Header none;  // stamp 0: the notice belongs to no scan
  refuse(none, ros::Time::now(), &InputCounters::bad_inputs, error);
}

void ScanSource::noPose(const std_msgs::Header& header, const ros::Time& receipt,
                        const std::string& error) {
  ScanEvent e;
  e.kind = ScanEvent::Kind::kNoPose;
  e.scan = noPoseInput(header, cfg_.fixed_frame, error);
  e.header = header;
  e.receipt = receipt;
  sink_(std::move(e));
}

void ScanSource::refuse(const std_msgs::Header& header, const ros::Time& receipt,
                        uint64_t InputCounters::*counter, const std::string& error) {
  stats_->count(counter, error);
  ROS_WARN_THROTTLE(5.0, "%s", error.c_str());
  ScanEvent e;
  e.kind = ScanEvent::Kind::kRefused;
  e.header = header;
  e.receipt = receipt;
  e.reason = error;
  sink_(std::move(e));
}

void ScanSource::countError(const std::string& error) {
  stats_->count(&InputCounters::errors, error);
  ROS_ERROR_THROTTLE(5.0, "%s", error.c_str());
}

}  // namespace ros_adapters
}  // namespace coral_introspection
