// The input side of CoralNodelet: subscribes `scan` (PointCloud2, or LaserScan with input_type
// laser_scan) or `polar_image` (mono8 Image), refuses what cannot be judged (stamp 0, malformed
// messages), waits for the sensor pose at the stamp through a tf2 MessageFilter (TF from its own
// TfFeed), converts each message (scan_input.hpp) and hands one ScanEvent per input message on: a
// posed scan, or a notice saying why it cannot be judged. Callbacks never throw. Policies
// (doc/online_behaviour.md):
//  - a scan whose TF is not there within tf_timeout [s of wall time] is a TF failure; if its
//    TF arrives later, the scan is counted as late and NOT judged (its no-verdict notice was
//    already sent, and newer scans may have been judged since);
//  - a scan stamp jumping back by more than TfFeed::kJumpBack clears the TF buffer when it
//    still holds the transforms of before the jump (looping bag), so the scan waits for the
//    replayed TF instead of failing;
//  - header.seq gaps per publisher count scans lost before the nodelet;
//  - an input topic published with another message type (polar images on `scan`, clouds on
//    `polar_image`) delivers nothing (roscpp drops such a connection before any callback):
//    checkInputTopic() asks the master, refuses it once and keeps it in the diagnostics.
#pragma once

#include <message_filters/subscriber.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>

#include <atomic>
#include <functional>
#include <memory>

#include "coral_introspection/ros/coral_diagnostics.hpp"
#include "coral_introspection/ros/coral_scan_input.hpp"
#include "coral_introspection/ros/coral_tf_feed.hpp"

namespace coral_introspection {
namespace ros_adapters {

// One input message on its way to the worker.
struct ScanEvent {
  enum class Kind {
    kScan,     // scan with its pose
    kNoPose,   // no TF (scan.pose_error says why); goes through the Introspector
    kRefused,  // cannot be judged at all (reason): stamp 0, malformed message
    kDropped,  // replaced in the mailbox by a newer scan while the worker was busy
  };
  Kind kind = Kind::kScan;
  online::ScanInput scan;
  std_msgs::Header header;
  ros::Time receipt;   // arrival in the nodelet (roscpp receipt time), for the latency
  std::string reason;  // kRefused, kDropped
};

// Empty when `published_type` (the input topic's message type as the master lists it; empty
// when nobody publishes it) is what a nodelet of `type` reads there; otherwise why none of
// the topic's messages can be received.
std::string inputTopicTypeError(const std::string& topic, const std::string& published_type,
                                InputType type);

class ScanSource {
 public:
  using Sink = std::function<void(ScanEvent event)>;
  // cfg: input_type, fixed_frame, queue_size, tf_timeout and the conversion parameters
  // (none of them reconfigurable). stats counts arrivals, refusals, late scans, TF clears.
  ScanSource(ros::NodeHandle& nh, const NodeConfig& cfg, Stats* stats, Sink sink);
  ~ScanSource();
  void subscribe(bool on);  // lazy input: only while an output has subscribers
  void expirePending();     // scans waiting for TF longer than tf_timeout: TF failures
  // While subscribed: the input topic's type from the master. A new mismatch is refused (one
  // REFUSED notice, stamp 0: no scan) and kept in the diagnostics until it is gone.
  void checkInputTopic();
  std::string topic() const;

 private:
  template <class M>
  using Event = ros::MessageEvent<M const>;
  template <class M>
  void setUp(message_filters::Subscriber<M>& sub, std::shared_ptr<tf2_ros::MessageFilter<M>>& f);
  template <class M>
  void onArrival(const Event<M>& event, tf2_ros::MessageFilter<M>& filter);
  template <class M>
  void onScan(const Event<M>& event);
  template <class M>
  void onFailure(const Event<M>& event, tf2_ros::FilterFailureReason reason);
  void noPose(const std_msgs::Header& header, const ros::Time& receipt, const std::string& error);
  void refuse(const std_msgs::Header& header, const ros::Time& receipt,
              uint64_t InputCounters::*counter, const std::string& error);
  void countError(const std::string& error);

  ros::NodeHandle nh_;
  const NodeConfig cfg_;
  Stats* stats_;
  Sink sink_;
  tf2_ros::Buffer tf_buffer_;
  TfFeed tf_feed_;
  online::BackwardsJump scan_jumps_{TfFeed::kJumpBack};  // input callbacks only (one thread)
  std::string topic_type_error_;                         // checkInputTopic (timer thread only)
  std::atomic<bool> subscribed_{false};                  // set by subscribe(), read by the timer
  message_filters::Subscriber<sensor_msgs::PointCloud2> cloud_sub_;
  message_filters::Subscriber<sensor_msgs::Image> image_sub_;
  message_filters::Subscriber<sensor_msgs::LaserScan> laser_sub_;
  std::shared_ptr<tf2_ros::MessageFilter<sensor_msgs::PointCloud2>> cloud_filter_;
  std::shared_ptr<tf2_ros::MessageFilter<sensor_msgs::Image>> image_filter_;
  std::shared_ptr<tf2_ros::MessageFilter<sensor_msgs::LaserScan>> laser_filter_;
};

}  // namespace ros_adapters
}  // namespace coral_introspection
