// Shared helpers of the CoralNodelet rostests: a constant-velocity trajectory through the
// synthetic yard, lidar clouds and plain polar radar images rendered from it, TF
// broadcasting and message collectors.
#pragma once

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/transform_broadcaster.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <random>

#include "coral_introspection/AlignmentQuality.h"
#include "coral_introspection/eval/synthetic.hpp"
#include "coral_introspection/radar/motion_compensation.hpp"
#include "coral_introspection/ros/conversions.hpp"

namespace coral_test {

using namespace coral_introspection;

// Sensor pose at time t [s] after the start: 3 m/s forward, turning at 0.3 rad/s.
inline Eigen::Isometry3d trajectory(double t) {
  radar::Twist v;
  v.linear = coral::Vec3(3.0, 0.0, 0.0);
  v.angular = coral::Vec3(0.0, 0.0, 0.3);
  return coral::se2(-5.0, -1.5, 0.1) * radar::constantVelocityPose(v, t);
}

inline sensor_msgs::PointCloud2 lidarCloud(const Eigen::Isometry3d& T_world_sensor,
                                           const ros::Time& stamp, const std::string& frame,
                                           std::mt19937& rng, int rings = 16) {
  eval::LidarModel m;
  m.rings = rings;
  if (rings == 1) m.v_min_deg = m.v_max_deg = 0.0;
  const coral::Points pts =
      eval::simulateScan(eval::SyntheticScene::structuredYard(), T_world_sensor, m, rng);
  std_msgs::Header h;
  h.stamp = stamp;
  h.frame_id = frame;
  return ros_adapters::pointsToCloud(pts, h);
}

// A planar laser scan of the yard from T_world_sensor: 361 beams of 0.5 deg from -90 deg (a
// SICK LMS in its 0.5 deg mode), 1 cm of range noise; no return written as range_max (30 m), as
// many drivers do.
inline sensor_msgs::LaserScan laserScan(const Eigen::Isometry3d& T_world_sensor,
                                        const ros::Time& stamp, const std::string& frame,
                                        std::mt19937& rng) {
  const auto scene = eval::SyntheticScene::structuredYard();
  std::normal_distribution<double> noise(0.0, 0.01);
  sensor_msgs::LaserScan s;
  s.header.stamp = stamp;
  s.header.frame_id = frame;
  s.angle_min = static_cast<float>(-M_PI / 2.0);
  s.angle_increment = static_cast<float>(M_PI / 360.0);
  s.angle_max = static_cast<float>(M_PI / 2.0);
  s.range_min = 0.1f;
  s.range_max = 30.0f;
  for (int i = 0; i < 361; ++i) {
    const double a = -M_PI / 2.0 + i * M_PI / 360.0;
    const coral::Vec3 d = T_world_sensor.linear() * coral::Vec3(std::cos(a), std::sin(a), 0.0);
    const auto range = scene.castRay(T_world_sensor.translation(), d, 29.0);
    s.ranges.push_back(range ? static_cast<float>(*range + noise(rng)) : s.range_max);
  }
  return s;
}

// Plain mono8 polar image (rows = ccw azimuths from +x, bin i = range i * res), row i seen
// from pose(t0 + i * period / rows): a moving, distorted scan like a real spinning radar.
template <class PoseFn>
sensor_msgs::Image polarImage(PoseFn pose, double t0, const ros::Time& stamp,
                              const std::string& frame, int rows = 400, int bins = 600,
                              double res = 0.1, double period = 0.25) {
  const auto scene = eval::SyntheticScene::structuredYard();
  sensor_msgs::Image im;
  im.header.stamp = stamp;
  im.header.frame_id = frame;
  im.encoding = sensor_msgs::image_encodings::MONO8;
  im.height = rows;
  im.width = bins;
  im.step = bins;
  im.data.assign(static_cast<std::size_t>(rows) * bins, 20);  // noise floor below z_min
  for (int r = 0; r < rows; ++r) {
    const Eigen::Isometry3d T = pose(t0 + r * period / rows);
    const double az = 2.0 * M_PI * r / rows;
    const coral::Vec3 d = T.linear() * coral::Vec3(std::cos(az), std::sin(az), 0.0);
    const auto range = scene.castRay(T.translation(), d, res * (bins - 3));
    if (!range) continue;
    const int b = static_cast<int>(std::lround(*range / res));
    for (int k = -2; k <= 2; ++k)
      if (b + k >= 0 && b + k < bins)
        im.data[r * bins + b + k] = static_cast<uint8_t>(220 - 30 * std::abs(k));
  }
  return im;
}

inline void sendTf(tf2_ros::TransformBroadcaster& br, const Eigen::Isometry3d& T,
                   const ros::Time& stamp, const std::string& child,
                   const std::string& parent = "odom") {
  geometry_msgs::TransformStamped ts = tf2::eigenToTransform(T);
  ts.header.stamp = stamp;
  ts.header.frame_id = parent;
  ts.child_frame_id = child;
  br.sendTransform(ts);
}

template <class M>
inline bool keepAll(const M&) {
  return true;
}
// What a Collector keeps by default: every message, except for AlignmentQuality only the
// pairs CorAl judged (status VERDICT or INVALID_PAIR); the messages saying why a scan has no
// verdict are collected with keepAll.
template <class M>
inline bool keepByDefault(const M&) {
  return true;
}
template <>
inline bool keepByDefault(const AlignmentQuality& m) {
  return m.status == AlignmentQuality::VERDICT || m.status == AlignmentQuality::INVALID_PAIR;
}

// Thread-safe store of the messages received on a topic (those `keep` accepts).
template <class M>
class Collector {
 public:
  Collector(ros::NodeHandle& nh, const std::string& topic,
            std::function<bool(const M&)> keep = keepByDefault<M>) {
    sub_ = nh.subscribe<M>(topic, 100, [this, keep](const boost::shared_ptr<const M>& m) {
      if (!keep(*m)) return;
      std::lock_guard<std::mutex> l(mutex_);
      msgs_.push_back(*m);
    });
  }
  std::size_t size() {
    std::lock_guard<std::mutex> l(mutex_);
    return msgs_.size();
  }
  std::vector<M> all() {
    std::lock_guard<std::mutex> l(mutex_);
    return std::vector<M>(msgs_.begin(), msgs_.end());
  }
  void clear() {
    std::lock_guard<std::mutex> l(mutex_);
    msgs_.clear();
  }
  // Waits (wall time) until at least n messages arrived.
  bool waitFor(std::size_t n, double timeout = 10.0) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::ok() && ros::WallTime::now() < end) {
      if (size() >= n) return true;
      ros::WallDuration(0.01).sleep();
    }
    return size() >= n;
  }
  ros::Subscriber& sub() { return sub_; }

 private:
  ros::Subscriber sub_;
  std::mutex mutex_;
  std::deque<M> msgs_;
};

// AlignmentQuality messages by the later scan's stamp (stamp_b): send a scan, then wait for
// its own verdict.
class VerdictsByStamp {
 public:
  VerdictsByStamp(ros::NodeHandle& nh, const std::string& topic) {
    sub_ = nh.subscribe<AlignmentQuality>(topic, 50, [this](const AlignmentQuality::ConstPtr& m) {
      std::lock_guard<std::mutex> l(mutex_);
      by_stamp_[m->stamp_b.toNSec()] = *m;
      cv_.notify_all();
    });
  }
  // Waits (wall time) for the verdict of the scan stamped `stamp`.
  bool waitFor(const ros::Time& stamp, double timeout, AlignmentQuality* out) {
    std::unique_lock<std::mutex> l(mutex_);
    const uint64_t key = stamp.toNSec();
    cv_.wait_for(l, std::chrono::duration<double>(timeout),
                 [&] { return by_stamp_.count(key) > 0; });
    if (!by_stamp_.count(key)) return false;
    *out = by_stamp_[key];
    return true;
  }
  void clear() {
    std::lock_guard<std::mutex> l(mutex_);
    by_stamp_.clear();
  }
  const ros::Subscriber& sub() const { return sub_; }

 private:
  ros::Subscriber sub_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::map<uint64_t, AlignmentQuality> by_stamp_;
};

// Polls `ok` (wall time) until it holds or the timeout passes; returns its last value.
inline bool waitUntil(const std::function<bool()>& ok, double timeout) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
  while (!ok() && ros::ok() && ros::WallTime::now() < end) ros::WallDuration(0.1).sleep();
  return ok();
}

inline bool waitForSubscriber(const ros::Publisher& pub, double timeout = 15.0) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::ok() && ros::WallTime::now() < end) {
    if (pub.getNumSubscribers() > 0) return true;
    ros::WallDuration(0.05).sleep();
  }
  return false;
}

}  // namespace coral_test
