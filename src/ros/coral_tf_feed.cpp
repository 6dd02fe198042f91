#include "coral_introspection/ros/coral_tf_feed.hpp"

#include <algorithm>
#include <sstream>

namespace coral_introspection {
namespace ros_adapters {

TfFeed::TfFeed(ros::NodeHandle nh, tf2_ros::Buffer* buffer,
               std::function<void(const std::string&)> on_clear)
    : buffer_(buffer), on_clear_(std::move(on_clear)) {
  nh.setCallbackQueue(&queue_);  // own thread: TF keeps flowing while callbacks are busy
  using Event = ros::MessageEvent<tf2_msgs::TFMessage const>;
  tf_sub_ = nh.subscribe<tf2_msgs::TFMessage>(
      "/tf", 100, boost::function<void(const Event&)>([this](const Event& e) { onTf(e, false); }),
      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  static_sub_ = nh.subscribe<tf2_msgs::TFMessage>(
      "/tf_static", 100,
      boost::function<void(const Event&)>([this](const Event& e) { onTf(e, true); }),
      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  spinner_ = std::make_unique<ros::AsyncSpinner>(1, &queue_);
  spinner_->start();
}

TfFeed::~TfFeed() {
  spinner_->stop();
  tf_sub_.shutdown();
  static_sub_.shutdown();
}

bool TfFeed::clearBefore(double stamp, const std::string& reason) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!(jumps_.newest() > stamp + kJumpBack)) return false;
  clearLocked(reason);
  // The stream is at `stamp` now, although no transform of the new loop has arrived yet:
  // without this, this very scan (and the next ones) would be posed from the snapshot and
  // overtake the old loop's last scan still waiting for its transform.
  jumped_to_ = stamp;
  return true;
}

void TfFeed::clearLocked(const std::string& reason) {
  // Keep what scans of before the jump may still need (see the header).
  before_jump_ = std::make_unique<tf2::BufferCore>();
  for (const auto& [child, r] : statics_)
    before_jump_->setTransform(r.transform, r.authority, true);
  for (const Received& r : recent_) before_jump_->setTransform(r.transform, r.authority, false);
  recent_.clear();
  buffer_->clear();
  jumps_.reset();
  jumped_to_ = 0.0;
  if (on_clear_) on_clear_(reason);
}

bool TfFeed::lookupBeforeJump(const std::string& target, const std::string& source,
                              const ros::Time& stamp, geometry_msgs::TransformStamped* out) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return lookupBeforeJumpLocked(target, source, stamp, out);
}

bool TfFeed::lookupBeforeJumpOrWait(const std::string& target, const std::string& source,
                                    const ros::Time& stamp, geometry_msgs::TransformStamped* out,
                                    const std::function<void()>& wait) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (lookupBeforeJumpLocked(target, source, stamp, out)) return true;
  wait();
  return false;
}

bool TfFeed::lookupBeforeJumpLocked(const std::string& target, const std::string& source,
                                    const ros::Time& stamp,
                                    geometry_msgs::TransformStamped* out) const {
  const double now = std::max(jumps_.newest(), jumped_to_);
  if (!before_jump_ || !(stamp.toSec() > now + kJumpBack)) return false;
  try {
    *out = before_jump_->lookupTransform(target, source, stamp);
    return true;
  } catch (const tf2::TransformException&) {
    return false;
  }
}

void TfFeed::insertLocked(const geometry_msgs::TransformStamped& t, const std::string& authority,
                          bool is_static) {
  if (is_static) {
    statics_[t.child_frame_id] = {t, authority};
  } else {
    recent_.push_back({t, authority});
    const double keep_from = jumps_.newest() - kKeep;
    while (recent_.size() > 10000 ||
           (!recent_.empty() && recent_.front().transform.header.stamp.toSec() < keep_from))
      recent_.pop_front();
  }
  try {
    buffer_->setTransform(t, authority, is_static);
  } catch (const std::exception& e) {  // tf2 reports bad data through its own log too
    ROS_WARN_THROTTLE(5.0, "TF from %s refused: %s", authority.c_str(), e.what());
  }
}

void TfFeed::onTf(const ros::MessageEvent<tf2_msgs::TFMessage const>& event, bool is_static) {
  const std::string authority = event.getPublisherName();
  std::lock_guard<std::mutex> lock(mutex_);
  const ros::Time now = ros::Time::now();
  if (now < last_now_) {
    std::ostringstream why;
    why << "ROS time jumped back by " << (last_now_ - now).toSec() << " s: TF buffer cleared";
    clearLocked(why.str());
  }
  last_now_ = now;
  for (const geometry_msgs::TransformStamped& t : event.getMessage()->transforms) {
    if (!is_static) {
      const double newest = jumps_.newest();
      if (jumps_.offer(t.child_frame_id, t.header.stamp.toSec())) {
        std::ostringstream why;
        why << "TF of '" << t.child_frame_id << "' jumped back in time (" << std::fixed << newest
            << " s -> " << t.header.stamp.toSec() << " s, looping bag?): TF buffer cleared";
        jumps_.reset();  // clearLocked resets too; the jump's stamp is re-offered below
        clearLocked(why.str());
        jumps_.offer(t.child_frame_id, t.header.stamp.toSec());
      }
    }
    insertLocked(t, authority, is_static);
  }
}

}  // namespace ros_adapters
}  // namespace coral_introspection
