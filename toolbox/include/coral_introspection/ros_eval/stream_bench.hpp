// Streaming a scan source into CoralNodelet and measuring what comes out, for the
// coral_stream_bench tool (sensor-rate and soak figures) and the overload rostest:
//  - CloudStreamer publishes one real cloud (e.g. a 64-beam lidar frame) seen from a moving
//    sensor: at time t the sensor is at T_fixed_sensor(t) (constant speed and yaw rate), the
//    cloud is the frame's points expressed in that sensor frame (+ Gaussian noise), stamped
//    t, with the TF fixed -> sensor at t on /tf just before it. Consecutive clouds are thus
//    truly aligned by their TF, and CorAl sees full-size real scans at the chosen rate.
//  - VerdictMonitor subscribes `alignment` and /diagnostics and summarises: verdicts per
//    second, latency (the message's own, arrival -> publication) and age (stamp -> receipt
//    here) quantiles, statuses, loops of a replayed bag, and the nodelet's counters.
//  - processRssMiB(nodePid(name)): resident memory of a running ROS node (same machine).
#pragma once

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "coral_introspection/AlignmentQuality.h"
#include "coral_introspection/coral/types.hpp"

namespace coral_introspection {
namespace ros_eval {

struct StreamOptions {
  double rate = 10.0;          // [Hz] clouds per second of wall time
  std::string topic = "scan";  // PointCloud2 topic (resolved in the node handle's namespace)
  std::string frame = "velodyne";
  std::string fixed_frame = "odom";
  double speed = 5.0;     // [m/s] forward speed of the sensor
  double yaw_rate = 0.1;  // [rad/s]
  double noise = 0.01;    // [m] standard deviation added to each coordinate
  int stride = 1;         // keep every stride-th point of the frame (smaller clouds)
};

class CloudStreamer {
 public:
  // world: the frame's points (they define the static scene, sensor at the origin at t = 0).
  CloudStreamer(ros::NodeHandle& nh, const coral::Points& world, const StreamOptions& options);
  // Waits (wall time) until the topic has a subscriber (the nodelet subscribes lazily).
  bool waitForSubscriber(double timeout_s) const;
  // Publishes TF and cloud for sensor time t [s] (pose T(t)) stamped `stamp`.
  void publish(double t, const ros::Time& stamp);
  // Publishes at options.rate for duration_s of wall time, stamped ros::Time::now();
  // returns the number of clouds. Stops early when ros::ok() turns false.
  std::size_t run(double duration_s);
  Eigen::Isometry3d pose(double t) const;  // T_fixed_sensor(t)
  std::size_t points() const { return world_.size(); }

 private:
  StreamOptions opt_;
  coral::Points world_;
  std::vector<float> noise_;  // pre-drawn: fresh noise per cloud without its cost
  std::mt19937 rng_{7};
  double t_ = 0.0;
  ros::Publisher pub_;
  tf2_ros::TransformBroadcaster tf_;
};

struct StreamSummary {
  double seconds = 0.0;      // [s] wall time of the window
  std::size_t messages = 0;  // AlignmentQuality messages
  std::map<uint8_t, std::size_t> by_status;
  std::size_t verdicts = 0;        // status VERDICT
  std::size_t judged = 0;          // VERDICT or INVALID_PAIR (CorAl ran)
  std::size_t without_reason = 0;  // no verdict (status != VERDICT) and an empty reason
  double verdict_rate = 0.0;       // [1/s]
  double latency_median = 0.0, latency_p95 = 0.0, latency_max = 0.0;  // [s] msg.latency
  double age_median = 0.0, age_p95 = 0.0;  // [s] receipt here - stamp_b (judged messages)
  std::size_t loops = 0;                   // complete loops (between two backward time jumps)
  std::size_t loops_judged = 0;            // ... where every scan after the first has a verdict
  std::string worst_loop;                  // description of a loop that was not fully judged
};

class VerdictMonitor {
 public:
  // node: the nodelet's name as it appears in the diagnostics status name (e.g. "coral").
  VerdictMonitor(ros::NodeHandle& nh, const std::string& alignment_topic, const std::string& node);
  void reset();  // forget what was received (start of a measuring window)
  StreamSummary summary();
  // Latest diagnostics values of the node (key -> value; "__message" = summary, "__level").
  std::map<std::string, std::string> diagnostics();
  // Every diagnostics summary of the node since reset() ("<level>: <message>"), in order.
  std::vector<std::string> diagnosticMessages();
  // Waits until at least n messages arrived since reset() (wall time).
  bool waitFor(std::size_t n, double timeout_s);
  std::size_t size();

 private:
  struct Sample {
    AlignmentQuality msg;
    double age = 0.0;
    ros::WallTime at;
  };
  std::string node_;
  std::mutex mutex_;
  std::vector<Sample> samples_;
  ros::WallTime since_;
  std::map<std::string, std::string> diag_;
  std::vector<std::string> diag_messages_;
  ros::Subscriber alignment_sub_, diag_sub_;
};

// Process id of a running ROS node (its XML-RPC getPid), nullopt when unknown.
std::optional<int> nodePid(const std::string& node);
// Resident set size of a process [MiB] (/proc/<pid>/status VmRSS), 0 when unreadable.
double processRssMiB(int pid);

}  // namespace ros_eval
}  // namespace coral_introspection
