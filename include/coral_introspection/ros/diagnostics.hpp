// What CoralNodelet's diagnostics report, collected from its threads: the adapter's own
// counters (messages received, bad inputs, callback errors), the Introspector's counters
// (pairs, verdicts, resets, TF failures, Doppler), scans dropped because the worker was busy,
// latency and processing time, and the scans still waiting for TF (tf_timeout). Every method
// takes one small mutex for a few operations: never held while CorAl runs.
#pragma once

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <ros/time.h>
#include <std_msgs/Header.h>

#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "coral_introspection/online/introspector.hpp"

namespace coral_introspection {
namespace ros_adapters {

struct InputCounters {
  uint64_t received = 0;           // scan messages
  uint64_t bad_inputs = 0;         // malformed / empty messages, refused check_alignment requests
  uint64_t non_finite_points = 0;  // NaN/Inf cloud points dropped
  uint64_t errors = 0;             // exceptions caught in callbacks
};

class Stats {
 public:
  bool doppler = false;  // report the Doppler counters (set before the threads start)

  // A scan message arrived: counted, and waits for TF until resolvePending() / expiry.
  void arrived(const std_msgs::Header& header);
  // True when the scan was still waiting for TF (then no longer).
  bool resolvePending(const std_msgs::Header& header);
  // Scans that waited longer than timeout [s] of wall time (removed).
  std::vector<std_msgs::Header> expirePending(double timeout);

  void count(uint64_t InputCounters::*counter, const std::string& error);
  void nonFinite(std::size_t n);
  // After each Introspector::process: its counters, the verdict latency (now - stamp), the
  // mailbox's dropped total, and the reason of a scan that could not be used.
  void processed(const online::Report& report, const ros::Time& stamp, uint64_t dropped);

  // diagnostic_updater task: WARN when problems arose since the last report.
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

 private:
  std::mutex mutex_;
  InputCounters input_, last_input_;
  online::Counters counters_, last_counters_;
  uint64_t dropped_ = 0;  // scans replaced in the mailbox before the worker took them
  double latency_sum_ = 0.0, last_latency_sum_ = 0.0;  // [s] over scans with a pose
  uint64_t with_pose_ = 0, last_with_pose_ = 0;
  ros::WallTime last_report_ = ros::WallTime::now();
  std::string last_error_;
  std::map<std::pair<std::string, ros::Time>, ros::WallTime> pending_;  // -> arrival
};

}  // namespace ros_adapters
}  // namespace coral_introspection
