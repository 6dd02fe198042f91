// The TF listener of CoralNodelet: fills the tf2 buffer the nodelet owns from /tf and
// /tf_static on a thread of its own (like tf2_ros::TransformListener), and clears the buffer
// when time jumps backwards, so a looping bag recovers at once:
//  - a transform stamped more than kJumpBack older than the newest one of its child frame
//    (`rosbag play -l` without --clock: stamps repeat, the clock does not; without the
//    clear, tf2 refuses the replayed transforms as TF_OLD_DATA for (bag length - cache
//    time) of every loop);
//  - ROS time itself going backwards (`rosbag play -l --clock`, as TransformListener does).
// Static transforms survive a clear (tf2 keeps them).
// Scans of before the jump that are still on their way (a scan message is larger than a
// transform, so the next loop's first transform often overtakes the previous loop's last
// scan; or the scan's lookup is still queued) are posed from a snapshot of the last
// kKeep seconds of transforms taken at the clear (lookupBeforeJump), not lost.
#pragma once

#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <tf2/buffer_core.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/buffer.h>

#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "coral_introspection/online/stream_checks.hpp"

namespace coral_introspection {
namespace ros_adapters {

class TfFeed {
 public:
  static constexpr double kJumpBack = 1.0;  // [s] larger backward steps are a time jump
  // on_clear(reason): called after each clear (counted and logged by the caller).
  TfFeed(ros::NodeHandle nh, tf2_ros::Buffer* buffer,
         std::function<void(const std::string&)> on_clear);
  ~TfFeed();
  // A scan stamped `stamp` [s] arrived after its own stream jumped back: clears the buffer
  // when it still holds transforms of before the jump (newest > stamp + kJumpBack), so the
  // scan waits for the new loop's transform instead of failing as too old. True if cleared.
  bool clearBefore(double stamp, const std::string& reason);
  // The pose target <- source at `stamp` for a scan of before the last clear: only when the
  // stamp is ahead of every transform received since and of the scan that caused the clear
  // (+ kJumpBack), so a scan of the new loop never gets a pose of the old one (nor overtakes
  // the old loop's last scan). False otherwise or when not in the snapshot.
  bool lookupBeforeJump(const std::string& target, const std::string& source,
                        const ros::Time& stamp, geometry_msgs::TransformStamped* out) const;
  // lookupBeforeJump, and when it fails, wait() (e.g. adding the scan to a tf2 MessageFilter)
  // under the same lock: a clear between the two would leave the scan waiting for a
  // transform that was received and cleared meanwhile (reported as late after tf_timeout).
  // wait() must not call back into this TfFeed.
  bool lookupBeforeJumpOrWait(const std::string& target, const std::string& source,
                              const ros::Time& stamp, geometry_msgs::TransformStamped* out,
                              const std::function<void()>& wait);

  static constexpr double kKeep = 3.0;  // [s] of transforms kept for lookupBeforeJump

 private:
  struct Received {
    geometry_msgs::TransformStamped transform;
    std::string authority;
  };
  void onTf(const ros::MessageEvent<tf2_msgs::TFMessage const>& event, bool is_static);
  void clearLocked(const std::string& reason);
  bool lookupBeforeJumpLocked(const std::string& target, const std::string& source,
                              const ros::Time& stamp, geometry_msgs::TransformStamped* out) const;
  void insertLocked(const geometry_msgs::TransformStamped& t, const std::string& authority,
                    bool is_static);

  tf2_ros::Buffer* buffer_;
  std::function<void(const std::string&)> on_clear_;
  mutable std::mutex mutex_;  // jumps_, last_now_, and clear + insert as one step
  online::BackwardsJump jumps_{kJumpBack};
  double jumped_to_ = 0.0;  // [s] stamp of the scan whose jump cleared (0: a TF clear)
  ros::Time last_now_;
  std::deque<Received> recent_;                   // non-static, stamps >= newest - kKeep
  std::map<std::string, Received> statics_;       // latest static transform per child frame
  std::unique_ptr<tf2::BufferCore> before_jump_;  // snapshot of recent_ + statics_ at a clear
  ros::CallbackQueue queue_;
  ros::Subscriber tf_sub_, static_sub_;
  std::unique_ptr<ros::AsyncSpinner> spinner_;
};

}  // namespace ros_adapters
}  // namespace coral_introspection
