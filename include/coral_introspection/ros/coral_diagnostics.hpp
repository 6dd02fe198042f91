// What CoralNodelet's diagnostics report, collected from its threads: the input side's
// counters (received, refused, late, lost upstream, TF clears), the worker's (dropped while
// busy, processing time, latency, time budget, what it is busy with) and the Introspector's
// (pairs, verdicts, resets, TF failures, Doppler). Overload (dropped scans, slow pairs) and
// TF failures are reported apart, so a busy worker is never blamed on TF. Every method takes
// one small mutex for a few operations: never held while CorAl runs.
#pragma once

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <ros/time.h>
#include <std_msgs/Header.h>

#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "coral_introspection/online/introspector.hpp"
#include "coral_introspection/online/stream_checks.hpp"

namespace coral_introspection {
namespace ros_adapters {

struct InputCounters {
  uint64_t received = 0;           // scan messages
  uint64_t lost_upstream = 0;      // missing before the nodelet (header.seq gaps per publisher)
  uint64_t unstamped = 0;          // refused: header.stamp = 0
  uint64_t bad_inputs = 0;         // malformed / empty messages, refused check_alignment requests
  uint64_t non_finite_points = 0;  // NaN/Inf cloud points dropped
  uint64_t late = 0;               // TF arrived after tf_timeout: reported failed, not judged
  uint64_t tf_clears = 0;          // TF buffer cleared: time jumped back
  uint64_t errors = 0;             // exceptions caught in callbacks
};

// What the worker did with one mailbox item.
struct WorkDone {
  const online::Counters* counters = nullptr;  // the Introspector's totals (when it ran)
  uint8_t status = 0;                          // AlignmentQuality::status of the scan
  std::string reason;                          // why there is no verdict (empty with one)
  bool problem = false;                        // the reason is a problem ("last error")
  double seconds = 0.0;                        // [s] worker wall time for the item
  double latency = 0.0;                        // [s] arrival -> publication (AlignmentQuality)
};

class Stats {
 public:
  // Set before the threads start.
  bool doppler = false;      // report the Doppler counters
  bool calibration = false;  // report the online self-calibration (calibration/enabled)
  double time_budget = 0.0;  // [s] worker time per scan reported when exceeded; 0 = off
  // The mailbox's totals (scans dropped, notices lost), read at each report so drops show
  // while the worker is stuck on one scan.
  std::function<std::pair<uint64_t, uint64_t>()> mailbox;

  // A scan message arrived from `publisher` (its caller id: header.seq gaps per publisher).
  void arrived(const std_msgs::Header& header, const std::string& publisher);
  // The input was unsubscribed (lazy): sequence numbers start afresh.
  void inputStopped();
  // The scan now waits for TF until resolvePending() or expirePending().
  void waitForTf(const std_msgs::Header& header, const ros::Time& receipt);
  // Its receipt time when the scan was still waiting for TF (then no longer).
  std::optional<ros::Time> resolvePending(const std_msgs::Header& header);
  // Scans that waited longer than timeout [s] of wall time (removed), with receipt times.
  std::vector<std::pair<std_msgs::Header, ros::Time>> expirePending(double timeout);

  void count(uint64_t InputCounters::*counter, const std::string& error);
  // Why no scan can arrive at all (the input topic carries another message type), or empty:
  // while set, every report is an ERROR led by it (a counter would warn only once).
  void inputTopicProblem(const std::string& problem);
  void nonFinite(std::size_t n);
  void late();
  void tfCleared();

  // The worker starts / finishes an item (scan at header.stamp).
  void started(const std_msgs::Header& header);
  void finished(const WorkDone& done);
  // The worker ran the self-calibration (Introspector::calibrate) after an item.
  void calibrated(const online::CalibrationStatus& status);
  void idle();  // after an item, also one that failed

  // diagnostic_updater task: WARN when problems arose since the last report, or while the
  // worker has been busy on one scan for longer than time_budget.
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

 private:
  struct Window {  // sums since the last report
    uint64_t items = 0, computed = 0, verdicts = 0, with_latency = 0, over_budget = 0;
    double seconds = 0.0, seconds_max = 0.0, latency = 0.0, latency_max = 0.0;
  };
  using Key = std::pair<std::string, ros::Time>;  // frame_id, stamp
  struct Pending {
    ros::WallTime arrival;
    ros::Time receipt;
  };

  std::mutex mutex_;
  InputCounters input_, last_input_;
  online::Counters counters_, last_counters_;
  online::CalibrationStatus calibration_;
  online::SequenceGaps seq_gaps_;
  uint64_t dropped_ = 0, last_dropped_ = 0, notices_lost_ = 0;
  uint64_t verdicts_ = 0, over_budget_ = 0;
  Window window_;
  ros::WallTime last_report_ = ros::WallTime::now();
  std::optional<std::pair<ros::WallTime, ros::Time>> busy_;  // since, scan stamp
  std::string last_error_, last_tf_failure_, last_no_verdict_, input_topic_problem_;
  std::multimap<Key, Pending> pending_;
};

}  // namespace ros_adapters
}  // namespace coral_introspection
